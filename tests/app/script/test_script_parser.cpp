// The script language: every command parses, and every mistake is reported
// with the file and line before anything runs.
#include <gtest/gtest.h>

#include "app/script/script_parser.hpp"

namespace nlsoft::console {
namespace {

using K = Command::Kind;

std::string error_of(const std::string& text) {
  try {
    parse_script(text, "tune.nls");
  } catch (const ScriptError& e) {
    return e.what();
  }
  return "";
}

TEST(ScriptParser, ParsesEveryCommand) {
  const Script s = parse_script(
      "# tuning session\n"
      "\n"
      "set Q 1e6 2e6 1e6\n"
      "set Q[1] 3e6\n"
      "get Lambda\n"
      "params save before.params\n"
      "params load tuned.params\n"
      "ref infinity period=8 a=4\n"
      "ref load swirl.csv hold=10\n"
      "run 10s label=\"base line\"\n"
      "   wait 250ms   # a comment after a command\n"
      "expect nrmse < 0.05\n"
      "expect lost == 0\n"
      "export csv out.csv\n"
      "echo hello   world\n"
      "sweep Q0 1e5 1e6 1e7 run 5s\n"
      "start label=manual\n"
      "hold\n"
      "resume\n"
      "stop\n",
      "tune.nls");
  ASSERT_EQ(s.commands.size(), 18u);
  EXPECT_EQ(s.commands[0].kind, K::Set);
  EXPECT_EQ(s.commands[0].line, 3);
  EXPECT_EQ(s.commands[0].values, (std::vector<std::string>{"1e6", "2e6", "1e6"}));
  EXPECT_EQ(s.commands[1].name, "Q[1]");
  EXPECT_EQ(s.commands[3].kind, K::ParamsSave);
  EXPECT_EQ(s.commands[4].kind, K::ParamsLoad);
  EXPECT_EQ(s.commands[5].kind, K::Ref);
  ASSERT_EQ(s.commands[5].options.size(), 2u);
  EXPECT_EQ(s.commands[5].options[0], (std::pair<std::string, std::string>{"period", "8"}));
  EXPECT_EQ(s.commands[6].kind, K::RefLoad);
  EXPECT_EQ(s.commands[6].name, "swirl.csv");
  EXPECT_EQ(s.commands[7].kind, K::Run);
  EXPECT_DOUBLE_EQ(s.commands[7].seconds, 10.0);
  EXPECT_EQ(s.commands[7].label, "base line");
  EXPECT_EQ(s.commands[8].kind, K::Wait);
  EXPECT_DOUBLE_EQ(s.commands[8].seconds, 0.25);
  EXPECT_EQ(s.commands[8].line, 11);
  EXPECT_EQ(s.commands[9].kind, K::Expect);
  EXPECT_EQ(s.commands[9].op, CmpOp::Lt);
  EXPECT_DOUBLE_EQ(s.commands[9].value, 0.05);
  EXPECT_EQ(s.commands[10].op, CmpOp::Eq);
  EXPECT_EQ(s.commands[11].kind, K::ExportCsv);
  EXPECT_EQ(s.commands[12].name, "hello   world");
  EXPECT_EQ(s.commands[13].kind, K::Sweep);
  EXPECT_EQ(s.commands[13].name, "Q0");
  EXPECT_EQ(s.commands[13].values.size(), 3u);
  EXPECT_DOUBLE_EQ(s.commands[13].seconds, 5.0);
  EXPECT_EQ(s.commands[14].label, "manual");
  EXPECT_EQ(s.commands[17].kind, K::Stop);
}

TEST(ScriptParser, AnIdentLineIsParsedAndItsWordsCheckedBeforeConnecting) {
  const Script s = parse_script("ident prbs 10min seed=3 band=0.1:2 joint amplitude=0.5 label=\"bench 1\"\n", "t.nls");
  ASSERT_EQ(s.commands.size(), 1u);
  const Command& c = s.commands[0];
  EXPECT_EQ(c.kind, Command::Kind::Ident);
  EXPECT_EQ(c.name, "prbs");
  EXPECT_EQ(c.seconds, 600.0);
  EXPECT_EQ(c.label, "bench 1");
  EXPECT_EQ(error_of("ident sine 10s\n"), "tune.nls:1: ident: 'sine' is not a signal; use steps, prbs, walk, chirp or aprbs");
  EXPECT_EQ(error_of("ident prbs 10s amplitude=2\n"),
            "tune.nls:1: ident: --amplitude 2 is outside (0, 1]: it is the fraction of each input's range the signal "
            "spans");
  EXPECT_EQ(error_of("ident prbs 10s seed=abc\n"), "tune.nls:1: ident: seed=abc is not a valid seed (0..4294967295)");
  EXPECT_EQ(error_of("ident prbs 10s band=2:1\n"),
            "tune.nls:1: ident: --band '2:1': the lower edge is above the upper one");
  EXPECT_EQ(error_of("ident prbs 10s colour=red\n").find("tune.nls:1: ident: unknown option 'colour=red'"), 0u);
  EXPECT_EQ(error_of("ident prbs\n").find("tune.nls:1: 'ident' needs more: ident SIGNAL DURATION"), 0u) << error_of("ident prbs\n");
}

// ident's capture words: y_from= names the file merged after the run,
// y_offset= its clock's offset, a number, and only with a file.
TEST(ScriptParser, AnIdentLineTakesACaptureAndItsOffset) {
  const Script s = parse_script("ident prbs 1min y_from=mocap.csv y_offset=-1.25\n", "t.nls");
  ASSERT_EQ(s.commands.size(), 1u);
  EXPECT_EQ(s.commands[0].capture, "mocap.csv");
  EXPECT_EQ(s.commands[0].seconds, 60.0);
  EXPECT_EQ(error_of("ident prbs 10s y_from=m.csv y_offset=soon\n"),
            "tune.nls:1: ident: y_offset=soon is not a number of seconds");
  EXPECT_EQ(error_of("ident prbs 10s y_offset=1\n"),
            "tune.nls:1: ident: y_offset= goes with y_from=FILE.csv (the capture whose clock it places)");
}

TEST(ScriptParser, ErrorsNameFileAndLine) {
  EXPECT_EQ(error_of("echo ok\n\nfly 3\n"),
            "tune.nls:3: unknown command 'fly'; commands: set get params ref run start stop hold neutral resume wait "
            "expect export echo note sweep tune ident");
  EXPECT_EQ(error_of("run 10\n"), "tune.nls:1: '10' needs a unit: 10s, 10ms or 10min");
  EXPECT_EQ(error_of("# c\nrun 5parsecs\n"), "tune.nls:2: '5parsecs': unknown unit 'parsecs' (use ms, s, min or h)");
  EXPECT_EQ(error_of("wait -1s\n"), "tune.nls:1: '-1s': a duration must be > 0");
  EXPECT_EQ(error_of("expect nrmse ~ 0.05\n"), "tune.nls:1: '~' is not a comparison; use < <= > >= == !=");
  EXPECT_EQ(error_of("expect nrmse < small\n"), "tune.nls:1: 'small' is not a number");
  EXPECT_NE(error_of("expect accuracy > 1\n").find("tune.nls:1: unknown metric 'accuracy'; known: rmse, nrmse"), std::string::npos);
  EXPECT_EQ(error_of("set Q\n"), "tune.nls:1: 'set' needs more: set NAME VALUES...  e.g. set Q 1e6 2e6 1e6");
  EXPECT_EQ(error_of("sweep Q0 1 2 3\n"), "tune.nls:1: usage: sweep PARAM V1 V2 ... run DURATION  e.g. sweep Q0 1e5 1e6 1e7 run 5s");
  EXPECT_EQ(error_of("echo \"unterminated\n"), "");  // echo takes the raw rest of the line
  EXPECT_EQ(error_of("run 5s label=\"open\n"), "tune.nls:1: unterminated \"quote\"");
  EXPECT_EQ(error_of("run 5s colour=red\n"), "tune.nls:1: 'run': unexpected 'colour=red'; usage: run DURATION [label=TEXT] [early=ok]");
  EXPECT_EQ(error_of("params edit x\n"), "tune.nls:1: params edit: expected save, load, reapply, diff or reset");
  EXPECT_EQ(error_of("export json x\n"), "tune.nls:1: export json: only 'export csv FILE' is supported");
  EXPECT_EQ(error_of("ref swirl scale\n"), "tune.nls:1: ref swirl: 'scale' is not key=value");
  EXPECT_EQ(error_of("get\n"), "tune.nls:1: 'get' needs more: get NAME");
  EXPECT_EQ(error_of("stop now\n"), "tune.nls:1: 'stop' takes fewer arguments: stop (extra: 'now')");
}

// Every line is parsed before the error is thrown, and the error carries
// every line's message, in order.
TEST(ScriptParser, EveryLineIsParsedAndEveryErrorReported) {
  try {
    parse_script("run ten seconds\necho fine\nfly 3\n\nwait -1s\n", "t.nls");
    FAIL() << "three bad lines parsed";
  } catch (const ScriptError& e) {
    EXPECT_EQ(e.count, 3u);
    EXPECT_EQ(e.line, 1);
    EXPECT_EQ(std::string(e.what()),
              "t.nls:1: 'ten' is not a duration (e.g. 5s, 250ms, 2min)\n"
              "t.nls:3: unknown command 'fly'; commands: set get params ref run start stop hold neutral resume wait "
              "expect export echo note sweep tune ident\n"
              "t.nls:5: '-1s': a duration must be > 0");
  }
}

TEST(ScriptParser, EarlyOkAndParamsReapply) {
  const Script s = parse_script("run 10s early=ok label=x\nrun 1s\nsweep b 1 2 run 1s early=ok\nparams reapply\n", "t.nls");
  ASSERT_EQ(s.commands.size(), 4u);
  EXPECT_TRUE(s.commands[0].allow_early);
  EXPECT_EQ(s.commands[0].label, "x");
  EXPECT_FALSE(s.commands[1].allow_early) << "a run that ends early fails by default";
  EXPECT_TRUE(s.commands[2].allow_early);
  EXPECT_EQ(s.commands[3].kind, K::ParamsReapply);
  auto error_of = [](const std::string& text) {
    try {
      parse_script(text, "t.nls");
    } catch (const ScriptError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error_of("run 1s early=maybe\n"),
            "t.nls:1: 'run': early=maybe: use early=ok (a run may end before its duration) or early=fail");
  EXPECT_EQ(error_of("start early=ok\n"), "t.nls:1: 'start': unexpected 'early=ok'; usage: start [label=TEXT]")
      << "early= belongs to timed runs only";
  EXPECT_EQ(error_of("params reapply now\n"), "t.nls:1: 'params' takes fewer arguments: params reapply (extra: 'now')");
}

TEST(ScriptParser, Comparisons) {
  EXPECT_TRUE(compare(0.01, CmpOp::Lt, 0.05));
  EXPECT_FALSE(compare(0.0, CmpOp::Ne, 0.0));
  EXPECT_TRUE(compare(3, CmpOp::Ge, 3));
}

// A directory reads as nothing and /dev/null too: neither is an empty script.
TEST(ScriptParser, ADirectoryOrADeviceIsNoScript) {
  auto error_of = [](const std::string& path) {
    try {
      parse_script_file(path);
    } catch (const ScriptError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error_of("/tmp"), "/tmp:0: cannot read script: it is a directory, not a script");
  EXPECT_EQ(error_of("/dev/null"), "/dev/null:0: cannot read script: it is a character device, not a script");
}

TEST(ScriptParser, ReadingAMissingFileIsLineZero) {
  try {
    parse_script_file("/nonexistent/tune.nls");
    FAIL();
  } catch (const ScriptError& e) {
    EXPECT_EQ(e.line, 0);
    EXPECT_NE(std::string(e.what()).find("/nonexistent/tune.nls:0: cannot read script"), std::string::npos);
  }
}

}  // namespace
}  // namespace nlsoft::console

namespace nlsoft::console {
namespace {

// A run that lost samples is judged only when the script says so.
TEST(ScriptParser, ExpectTakesLostOkAndNothingElse) {
  const Script s = parse_script("expect max_error < 0.1\nexpect max_error < 0.1 lost=ok\n", "t.nls");
  ASSERT_EQ(s.commands.size(), 2u);
  EXPECT_FALSE(s.commands[0].allow_lost);
  EXPECT_TRUE(s.commands[1].allow_lost);
  EXPECT_NE(error_of("expect max_error < 0.1 lost=maybe\n").find("tune.nls:1: expect: unexpected 'lost=maybe'"),
            std::string::npos)
      << error_of("expect max_error < 0.1 lost=maybe\n");
}

}  // namespace
}  // namespace nlsoft::console
