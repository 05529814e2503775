"""Boots an nlsoft Cortex-M image in qemu-system-arm with its link's UART
on a pseudo-terminal and -icount shift=0 (1 ns of virtual time per
instruction), and finds the pty QEMU reports. BOARDS: the tools' view of the
console's board table (host/rig/board_table.cpp), which these scripts cannot
read; tests/host/rig/test_board_table.cpp holds the two equal."""
import re
import shutil
import subprocess
import time

QEMU = "qemu-system-arm"
import os
ICOUNT = os.environ.get("NLSOFT_ICOUNT", "shift=0")


# Per board: the port folder, the image folder under build/firmware/, the
# image prefix, and QEMU's machine with the -serial arguments that put the
# link's UART on the pty (mps2: UART0, the first serial port; stm32f4:
# USART2 of -M netduinoplus2, the second).
BOARDS = {
    "mps2-an386": ("firmware/ports/mps2-an386", "m4", "nlsoft-m4", ["-M", "mps2-an386", "-serial", "pty"]),
    "stm32f4": ("firmware/ports/stm32f4", "stm32f4", "nlsoft-stm32f4",
                ["-M", "netduinoplus2", "-serial", "null", "-serial", "pty"]),
    "mps2-an500": ("firmware/ports/mps2-an500", "m7", "nlsoft-m7", ["-M", "mps2-an500", "-serial", "pty"]),
    "mps2-an385": ("firmware/ports/mps2-an385", "m3", "nlsoft-m3", ["-M", "mps2-an385", "-serial", "pty"]),
}


def available():
    return shutil.which(QEMU) is not None


class Qemu:
    def __init__(self, elf, timeout=10.0, board="mps2-an386"):
        machine = BOARDS[board][3]
        self.proc = subprocess.Popen(
            [QEMU] + machine + ["-nographic", "-monitor", "none", "-icount", ICOUNT, "-kernel", elf],
            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.pty = None
        deadline = time.monotonic() + timeout
        # "char device redirected to /dev/pts/N (label serial0)"
        while self.pty is None and time.monotonic() < deadline:
            line = self.proc.stdout.readline()
            if not line:
                break
            m = re.search(r"redirected to (/dev/\S+)", line)
            if m:
                self.pty = m.group(1)
        if self.pty is None:
            self.close()
            raise RuntimeError("qemu-system-arm reported no pty for " + elf)

    def close(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(5)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
