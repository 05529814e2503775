# The chip and servo drivers, listed once: the host build's library
# (firmware/drivers/CMakeLists.txt) and every Cortex-M image
# (ports/cortex-m/images.cmake) compile this list.
set(NLSOFT_DRIVER_SOURCES register_bus.cpp lis3mdl.cpp lsm303dlhc_mag.cpp dps310.cpp max1111.cpp dynamixel_packet.cpp
    dynamixel_servo.cpp)
