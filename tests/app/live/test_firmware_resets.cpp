// Reset forensics in process (FirmwareResets): a board that started again
// behind a reconnect is noticed, the edits it lost named and sent again.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <fmt/format.h>

#include <chrono>
#include <mutex>
#include <thread>

#include "app/link/sim_launcher.hpp"
#include "app/live/live_console.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {
namespace {

// A board that resets while the link is down (here: the port's name now
// leads to a freshly started firmware) has forgotten the session's edits.
// The console notices by the firmware's uptime, re-reads the parameters,
// names the edits lost, and sends them again on request.
TEST(FirmwareReset, EditsLostToAResetAreNamedAndSentAgain) {
  ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
  test::TempDir dir;
  auto first = std::make_unique<SimLauncher>();
  const std::string board = dir.file("board");
  ASSERT_EQ(::symlink(first->start("msd").c_str(), board.c_str()), 0);
  LiveOptions o;
  o.port = board;
  o.db_path = dir.file("runs.db");
  // Before the console: its link threads may still say something while it
  // shuts down.
  std::mutex mu;
  std::vector<std::string> said;
  LiveConsole console(o);
  console.notices().listen([&](const std::string& l) {
    std::lock_guard<std::mutex> lock(mu);
    said.push_back(l);
  });
  console.connect();
  const std::vector<double> lambda = console.params().get("Lambda").second;
  console.params().set("Lambda", {fmt::format("{:g}", lambda[0] * 4)});
  // The second firmware must boot well after the first (the console allows
  // half a second of reply latency in its boot-time estimate).
  std::this_thread::sleep_for(std::chrono::seconds(2));
  // The link goes first: the dead firmware's pty may be anyone's next.
  ASSERT_EQ(::unlink(board.c_str()), 0);
  first.reset();
  SimLauncher second;
  ASSERT_EQ(::symlink(second.start("msd").c_str(), board.c_str()), 0);
  for (int i = 0; i < 1500 && console.resets().count() == 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_EQ(console.resets().count(), 1u);
  const auto forgotten = console.resets().forgotten();
  ASSERT_EQ(forgotten.size(), 1u);
  EXPECT_EQ(forgotten[0].rfind("Lambda is ", 0), 0u) << forgotten[0];
  {
    std::lock_guard<std::mutex> lock(mu);
    std::string all;
    for (const auto& l : said) all += l + "\n";
    EXPECT_NE(all.find("the firmware has reset (its uptime says it started again"), std::string::npos) << all;
    EXPECT_NE(all.find("1 edit is no longer in force"), std::string::npos) << all;
  }
  EXPECT_FLOAT_EQ(float(console.params().get("Lambda").second[0]), float(lambda[0])) << "the new firmware's default";
  const auto sent = console.resets().reapply();
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_FLOAT_EQ(float(console.params().get("Lambda").second[0]), float(lambda[0] * 4));
  EXPECT_TRUE(console.resets().forgotten().empty());
}

}  // namespace
}  // namespace nlsoft::console
