// The connection in process (LiveConsole): a port that is not there yet
// is waited for with --wait, and refused at once without it.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <chrono>
#include <mutex>
#include <thread>

#include "app/link/sim_launcher.hpp"
#include "app/live/live_console.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {
namespace {

// --wait: a board plugged in after the console started is connected to;
// without --wait a missing port fails at once and says how to wait.
TEST(LiveConsoleWait, APortThatAppearsLaterIsConnectedTo) {
  ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
  test::TempDir dir;
  SimLauncher sim;
  const std::string pty = sim.start("msd");
  LiveOptions o;
  o.port = dir.file("ttyACM7");
  o.db_path = dir.file("runs.db");
  o.wait = std::chrono::milliseconds(30000);
  std::mutex mu;
  std::vector<std::string> said;  // before the console, which may still say something while it shuts down
  LiveConsole console(o);
  std::thread plug([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    (void)::symlink(pty.c_str(), o.port.c_str());
  });
  console.notices().listen([&](const std::string& l) {
    std::lock_guard<std::mutex> lock(mu);
    said.push_back(l);
  });
  EXPECT_NO_THROW(console.connect());
  plug.join();
  EXPECT_EQ(console.rig().name, "msd");
  std::lock_guard<std::mutex> lock(mu);
  ASSERT_FALSE(said.empty());
  EXPECT_EQ(said.front().rfind("waiting up to 30 s for " + o.port, 0), 0u) << said.front();
}

TEST(LiveConsoleWait, AMissingPortFailsAtOnceOrAfterTheWait) {
  test::TempDir dir;
  LiveOptions o;
  o.port = dir.file("ttyACM7");
  o.db_path = dir.file("runs.db");
  try {
    LiveConsole(o).connect();
    FAIL() << "connected to nothing";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist: is the board plugged in? --wait SECONDS"), std::string::npos)
        << e.what();
  }
  o.wait = std::chrono::milliseconds(200);
  try {
    LiveConsole(o).connect();
    FAIL() << "connected to nothing";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("did not appear within 0.2 s"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nlsoft::console
