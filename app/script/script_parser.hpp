#pragma once
// The script language (`--script FILE` and the TUI's `:` line), parsed
// apart from execution so every syntax error is found, with its line
// number, before anything is sent to the firmware.
//
//   # comment
//   set NAME VALUES...        set Q 1e6 2e6 1e6   |  set Q[1] 2e6
//   get NAME
//   params save FILE | params load FILE | params reapply | params diff | params reset
//   ref NAME key=value...     ref infinity period=8 a=4
//   ref load FILE.csv [hold=N]
//   model upload FILE.nlsm
//   run DURATION [label=TEXT] [early=ok]
//                             run 10s label="baseline"; a run that ends before
//                             DURATION (firmware stopped, watchdog) fails the
//                             script unless early=ok
//   start [label=TEXT] | stop | hold | neutral | resume
//   wait DURATION
//   expect METRIC OP VALUE    expect nrmse < 0.05   (OP: < <= > >= == !=)
//   export csv FILE
//   echo TEXT
//   settings save|defaults|report   SETTINGS (PROTOCOL.md 9.11)
//   note TEXT                 notes on the current (or last) run
//   sweep PARAM V1 V2 ... run DURATION [settle=DURATION] [label=TEXT] [early=ok]
//   tune NAME=LO..HI[:log|:lin]... [objective=EXPR] [budget=N|DURATION] [apply] ...
//                             (app/tune/tune_options.hpp)
//   ident SIGNAL DURATION [seed=N] [amplitude=F] [band=LO:HI] [joint|mixed] [decimation=N] [label=TEXT] [early=ok]
//                             an identification run (app/live/ident_plan.hpp)
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace nlsoft::console {

struct ScriptError : std::runtime_error {
  ScriptError(const std::string& f, int l, const std::string& msg)
      : std::runtime_error(f + ":" + std::to_string(l) + ": " + msg), file(f), line(l), message(msg) {}
  // Every error of a script checked whole: what() is one "file:LINE:
  // message" a line; file, line and message are the first one's.
  explicit ScriptError(const std::vector<ScriptError>& all);
  std::string file;
  int line;
  std::string message;
  size_t count = 1;
};

enum class CmpOp { Lt, Le, Gt, Ge, Eq, Ne };
const char* cmp_op_text(CmpOp op);
bool compare(double lhs, CmpOp op, double rhs);

struct Command {
  enum class Kind {
    Set, Get, ParamsSave, ParamsLoad, ParamsReapply, ParamsDiff, ParamsReset, Ref, RefLoad, ModelUpload, Run, Start, Stop, Hold, Neutral, Resume,
    Wait, Expect, ExportCsv, Echo, Sweep, Note, Tune, Ident, Devices, Settings,
  };
  Kind kind = Kind::Echo;
  int line = 0;
  std::string text;                 // the source line, trimmed
  std::string name;                 // parameter, reference, metric, file or echo text
  std::vector<std::string> values;  // set / sweep values; tune's words
  std::vector<std::pair<std::string, std::string>> options;  // key=value
  double seconds = 0;               // run / wait / sweep duration
  CmpOp op = CmpOp::Lt;
  double value = 0;                 // expect
  std::string label;                // run / start / sweep
  bool allow_early = false;         // run / sweep: early=ok
  bool allow_lost = false;          // expect: lost=ok (a run with lost samples may be judged)
  double settle_s = 1.0;            // sweep: seconds each row runs before it is measured
  std::string capture;              // ident: y_from=FILE.csv, merged into the run once recorded
};

struct Script {
  std::string file;
  std::vector<Command> commands;
};

// Parses one line (already known not to be blank or a comment). Throws
// ScriptError(file, line, ...).
Command parse_command(const std::string& line, const std::string& file, int lineno);

// Parses a whole script: every line is parsed, and one ScriptError carrying
// every line's error is thrown at the end. Blank lines and lines whose first
// non-blank is '#' are skipped.
Script parse_script(const std::string& text, const std::string& file);
// ScriptError (line 0) for what cannot be read, or is no script: a missing
// file, a directory, a device.
Script parse_script_file(const std::string& path);

// One line of help per command, for --help, F1 and `:help`.
const std::vector<std::string>& script_help();

}  // namespace nlsoft::console
