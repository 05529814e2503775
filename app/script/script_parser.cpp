#include "app/script/script_parser.hpp"

#include <fmt/format.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "host/files/cli_error.hpp"
#include "host/files/input_file.hpp"
#include "host/files/printable.hpp"
#include "app/live/ident_plan.hpp"
#include "app/record/run_metrics.hpp"
#include "app/script/ident_words.hpp"
#include "app/text/duration.hpp"
#include "app/text/tokenize.hpp"
#include "app/tune/tune_options.hpp"

namespace nlsoft::console {

using host::CliError;
using host::kScriptFile;
using host::printable;
using host::read_input_file;

namespace {

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

bool split_option(const std::string& tok, std::pair<std::string, std::string>& kv) {
  const size_t eq = tok.find('=');
  if (eq == std::string::npos || eq == 0) return false;
  kv = {tok.substr(0, eq), tok.substr(eq + 1)};
  return true;
}

std::string metric_list() {
  std::string s;
  for (const auto& m : metric_names()) s += (s.empty() ? "" : ", ") + m;
  return s;
}

}  // namespace

const char* cmp_op_text(CmpOp op) {
  switch (op) {
    case CmpOp::Lt: return "<";
    case CmpOp::Le: return "<=";
    case CmpOp::Gt: return ">";
    case CmpOp::Ge: return ">=";
    case CmpOp::Eq: return "==";
    case CmpOp::Ne: return "!=";
  }
  return "?";
}

bool compare(double a, CmpOp op, double b) {
  switch (op) {
    case CmpOp::Lt: return a < b;
    case CmpOp::Le: return a <= b;
    case CmpOp::Gt: return a > b;
    case CmpOp::Ge: return a >= b;
    case CmpOp::Eq: return a == b;
    case CmpOp::Ne: return a != b;
  }
  return false;
}

namespace {

std::string join_errors(const std::vector<ScriptError>& all) {
  std::string s;
  for (const ScriptError& e : all) s += (s.empty() ? "" : "\n") + std::string(e.what());
  return s;
}

}  // namespace

ScriptError::ScriptError(const std::vector<ScriptError>& all)
    : std::runtime_error(join_errors(all)),
      file(all.at(0).file),
      line(all.at(0).line),
      message(all.at(0).message),
      count(all.size()) {}

namespace {

// A command line's words, and the ways a verb's parser refuses them: each
// message names the script's file and line, and quotes the words escaped.
struct Words {
  const std::vector<std::string>& t;
  const std::string& line;  // trimmed, for echo's free text
  const std::string& file;
  int lineno;

  const std::string& verb() const { return t[0]; }
  ScriptError fail(const std::string& msg) const { return ScriptError(file, lineno, printable(msg)); }
  void need(size_t n, const char* usage) const {
    if (t.size() < n) throw fail(fmt::format("'{}' needs more: {}", verb(), usage));
  }
  void at_most(size_t n, const char* usage) const {
    if (t.size() > n) throw fail(fmt::format("'{}' takes fewer arguments: {} (extra: '{}')", verb(), usage, t[n]));
  }
  double duration(const std::string& s) const {
    try {
      return text::parse_duration(s);
    } catch (const std::invalid_argument& e) {
      throw fail(e.what());
    }
  }
  // label=TEXT everywhere; early=ok on timed runs, where a run that ends
  // before its duration is otherwise a failure; settle= on a sweep's rows.
  void label_options(Command& c, size_t from, const char* usage, bool timed = false, bool settles = false) const {
    for (size_t i = from; i < t.size(); ++i) {
      std::pair<std::string, std::string> kv;
      const bool ok = split_option(t[i], kv) && (kv.first == "label" || (timed && kv.first == "early") ||
                                                 (settles && kv.first == "settle"));
      if (!ok) throw fail(fmt::format("'{}': unexpected '{}'; usage: {}", verb(), t[i], usage));
      if (kv.first == "settle") {
        c.settle_s = kv.second == "0" ? 0.0 : duration(kv.second);
      } else if (kv.first == "label") {
        c.label = kv.second;
      } else if (kv.second == "ok") {
        c.allow_early = true;
      } else if (kv.second != "fail") {
        throw fail(fmt::format("'{}': early={}: use early=ok (a run may end before its duration) or early=fail",
                               verb(), kv.second));
      }
    }
  }
};

void parse_set(const Words& w, Command& c) {
  w.need(3, "set NAME VALUES...  e.g. set Q 1e6 2e6 1e6");
  c.kind = Command::Kind::Set;
  c.name = w.t[1];
  c.values.assign(w.t.begin() + 2, w.t.end());
}

void parse_get(const Words& w, Command& c) {
  w.need(2, "get NAME");
  w.at_most(2, "get NAME");
  c.kind = Command::Kind::Get;
  c.name = w.t[1];
}

void parse_params(const Words& w, Command& c) {
  w.need(2, "params save FILE | params load FILE | params reapply | params diff | params reset");
  const std::string& sub = w.t[1];
  if (sub == "reapply" || sub == "diff" || sub == "reset") {
    w.at_most(2, ("params " + sub).c_str());
    c.kind = sub == "reapply" ? Command::Kind::ParamsReapply
           : sub == "diff"    ? Command::Kind::ParamsDiff
                              : Command::Kind::ParamsReset;
  } else if (sub == "save" || sub == "load") {
    const std::string usage = "params " + sub + " FILE";
    w.need(3, usage.c_str());
    w.at_most(3, usage.c_str());
    c.kind = sub == "save" ? Command::Kind::ParamsSave : Command::Kind::ParamsLoad;
    c.name = w.t[2];
  } else {
    throw w.fail(fmt::format("params {}: expected save, load, reapply, diff or reset", sub));
  }
}

void parse_model(const Words& w, Command& c) {
  w.need(3, "model upload FILE.nlsm");
  w.at_most(3, "model upload FILE.nlsm");
  if (w.t[1] != "upload") throw w.fail(fmt::format("model {}: expected 'upload' (model upload FILE.nlsm)", w.t[1]));
  c.kind = Command::Kind::ModelUpload;
  c.name = w.t[2];
}

void parse_ref(const Words& w, Command& c) {
  const std::vector<std::string>& t = w.t;
  w.need(2, "ref NAME key=value...  or  ref load FILE.csv [hold=N]");
  if (t[1] == "load") {
    w.need(3, "ref load FILE.csv [hold=N]");
    c.kind = Command::Kind::RefLoad;
    c.name = t[2];
    for (size_t i = 3; i < t.size(); ++i) {
      std::pair<std::string, std::string> kv;
      if (!split_option(t[i], kv) || kv.first != "hold")
        throw w.fail(fmt::format("ref load: unexpected '{}'; only hold=N", t[i]));
      c.options.push_back(kv);
    }
  } else {
    c.kind = Command::Kind::Ref;
    c.name = t[1];
    for (size_t i = 2; i < t.size(); ++i) {
      std::pair<std::string, std::string> kv;
      if (!split_option(t[i], kv)) throw w.fail(fmt::format("ref {}: '{}' is not key=value", c.name, t[i]));
      c.options.push_back(kv);
    }
  }
}

void parse_run(const Words& w, Command& c) {
  w.need(2, "run DURATION [label=TEXT] [early=ok]  e.g. run 10s label=baseline");
  c.kind = Command::Kind::Run;
  c.seconds = w.duration(w.t[1]);
  w.label_options(c, 2, "run DURATION [label=TEXT] [early=ok]", true);
}

void parse_start(const Words& w, Command& c) {
  c.kind = Command::Kind::Start;
  w.label_options(c, 1, "start [label=TEXT]");
}

// A verb on its own: stop, hold, neutral, resume, devices.
template <Command::Kind kind>
void parse_bare(const Words& w, Command& c) {
  w.at_most(1, w.verb().c_str());
  c.kind = kind;
}

void parse_settings(const Words& w, Command& c) {
  w.need(2, "settings save|defaults|report");
  w.at_most(2, "settings save|defaults|report");
  const std::string& what = w.t[1];
  if (what != "save" && what != "defaults" && what != "report")
    throw w.fail(fmt::format("'settings {}': say settings save (the parameters in force survive a reset), settings "
                             "defaults (the built-in ones back) or settings report (where they came from)",
                             what));
  c.kind = Command::Kind::Settings;
  c.name = what;
}

void parse_wait(const Words& w, Command& c) {
  w.need(2, "wait DURATION");
  w.at_most(2, "wait DURATION");
  c.kind = Command::Kind::Wait;
  c.seconds = w.duration(w.t[1]);
}

CmpOp comparison(const Words& w, const std::string& op) {
  if (op == "<") return CmpOp::Lt;
  if (op == "<=") return CmpOp::Le;
  if (op == ">") return CmpOp::Gt;
  if (op == ">=") return CmpOp::Ge;
  if (op == "==" || op == "=") return CmpOp::Eq;
  if (op == "!=") return CmpOp::Ne;
  throw w.fail(fmt::format("'{}' is not a comparison; use < <= > >= == !=", op));
}

void parse_expect(const Words& w, Command& c) {
  const std::vector<std::string>& t = w.t;
  w.need(4, "expect METRIC OP VALUE [lost=ok]  e.g. expect nrmse < 0.05");
  w.at_most(5, "expect METRIC OP VALUE [lost=ok]");
  // A run with lost samples (frames lost on the link, or refused: values
  // not finite, dimensions other than INFO's) was scored on part of it:
  // an expect on it fails unless the script says that is fine.
  if (t.size() == 5) {
    std::pair<std::string, std::string> kv;
    if (!split_option(t[4], kv) || kv.first != "lost" || (kv.second != "ok" && kv.second != "fail"))
      throw w.fail(fmt::format("expect: unexpected '{}'; only lost=ok (or lost=fail, the default)", t[4]));
    c.allow_lost = kv.second == "ok";
  }
  c.kind = Command::Kind::Expect;
  c.name = t[1];
  if (!known_metric(c.name)) throw w.fail(fmt::format("unknown metric '{}'; known: {}", c.name, metric_list()));
  c.op = comparison(w, t[2]);
  char* end = nullptr;
  c.value = std::strtod(t[3].c_str(), &end);
  if (end == t[3].c_str() || *end != '\0' || !std::isfinite(c.value))
    throw w.fail(fmt::format("'{}' is not a number", t[3]));
}

void parse_export(const Words& w, Command& c) {
  w.need(3, "export csv FILE");
  w.at_most(3, "export csv FILE");
  if (w.t[1] != "csv") throw w.fail(fmt::format("export {}: only 'export csv FILE' is supported", w.t[1]));
  c.kind = Command::Kind::ExportCsv;
  c.name = w.t[2];
}

// A quoted "echo" is only known as the verb once tokenized.
void parse_echo(const Words& w, Command& c) {
  c.kind = Command::Kind::Echo;
  c.name = trim(w.line.substr(4));
}

// sweep PARAM V1 V2 ... run DURATION [label=TEXT]
void parse_sweep(const Words& w, Command& c) {
  const std::vector<std::string>& t = w.t;
  size_t run_at = 0;
  for (size_t i = 2; i < t.size(); ++i)
    if (t[i] == "run") run_at = i;
  if (t.size() < 5 || run_at < 3 || run_at + 1 >= t.size())
    throw w.fail("usage: sweep PARAM V1 V2 ... run DURATION  e.g. sweep Q0 1e5 1e6 1e7 run 5s");
  c.kind = Command::Kind::Sweep;
  c.name = t[1];
  c.values.assign(t.begin() + 2, t.begin() + long(run_at));
  c.seconds = w.duration(t[run_at + 1]);
  w.label_options(c, run_at + 2, "sweep PARAM V1 V2 ... run DURATION [settle=DURATION] [label=TEXT] [early=ok]", true,
                  true);
}

void parse_tune(const Words& w, Command& c) {
  c.kind = Command::Kind::Tune;
  c.values.assign(w.t.begin() + 1, w.t.end());
  // Every word is checked now; the names against the firmware when it runs.
  try {
    parse_tune_words(c.values);
  } catch (const std::invalid_argument& e) {
    throw w.fail(e.what());
  }
}

void parse_ident(const Words& w, Command& c) {
  const std::vector<std::string>& t = w.t;
  const char* usage =
      "ident SIGNAL DURATION [seed=N] [amplitude=F] [band=LO:HI] [joint|mixed] [decimation=N] [label=TEXT] "
      "[early=ok] [y_from=FILE.csv [y_offset=S]]  e.g. ident prbs 10min seed=3";
  w.need(3, usage);
  c.kind = Command::Kind::Ident;
  c.name = t[1];
  c.values = {t[2]};
  IdentWords words = ident_words(c);
  for (size_t i = 3; i < t.size(); ++i) {
    std::pair<std::string, std::string> kv;
    if (t[i] == "joint" || t[i] == "mixed") kv = {t[i], "1"};
    else if (!split_option(t[i], kv)) throw w.fail(fmt::format("ident: '{}' is not key=value; usage: {}", t[i], usage));
    if (kv.first == "label") c.label = kv.second;
    else if (kv.first == "early" && kv.second == "ok") c.allow_early = true;
    else if (kv.first == "y_from") c.capture = kv.second;
    else if (kv.first == "y_offset") {
      // Checked now, not after the run: a typo must not cost a run's merge.
      char* end = nullptr;
      const double v = std::strtod(kv.second.c_str(), &end);
      if (kv.second.empty() || *end != '\0' || !std::isfinite(v))
        throw w.fail(fmt::format("ident: y_offset={} is not a number of seconds", kv.second));
      c.options.push_back(kv);
    }
    else if (kv.first == "seed" || kv.first == "amplitude" || kv.first == "band" || kv.first == "joint" ||
             kv.first == "mixed" || kv.first == "decimation")
      c.options.push_back(kv);
    else throw w.fail(fmt::format("ident: unknown option '{}'; usage: {}", t[i], usage));
  }
  if (c.capture.empty() && std::any_of(c.options.begin(), c.options.end(), [](const auto& o) { return o.first == "y_offset"; }))
    throw w.fail("ident: y_offset= goes with y_from=FILE.csv (the capture whose clock it places)");
  try {
    words = ident_words(c);
    c.seconds = check_ident_words(words);
  } catch (const std::exception& e) {
    throw w.fail(e.what());
  }
}

// Every verb a script line can start with, and its parser.
struct Verb {
  const char* name;
  void (*parse)(const Words& w, Command& c);
};
const Verb kVerbs[] = {
    {"set", parse_set},
    {"get", parse_get},
    {"params", parse_params},
    {"model", parse_model},
    {"ref", parse_ref},
    {"run", parse_run},
    {"start", parse_start},
    {"stop", parse_bare<Command::Kind::Stop>},
    {"hold", parse_bare<Command::Kind::Hold>},
    {"neutral", parse_bare<Command::Kind::Neutral>},
    {"resume", parse_bare<Command::Kind::Resume>},
    {"devices", parse_bare<Command::Kind::Devices>},
    {"settings", parse_settings},
    {"wait", parse_wait},
    {"expect", parse_expect},
    {"export", parse_export},
    {"echo", parse_echo},
    {"sweep", parse_sweep},
    {"tune", parse_tune},
    {"ident", parse_ident},
};

}  // namespace

Command parse_command(const std::string& raw, const std::string& file, int lineno) {
  const std::string line = trim(raw);
  const std::string first = line.substr(0, line.find_first_of(" \t"));
  if (first == "echo" || first == "note") {
    // Free text: quotes and all are kept as written.
    Command c;
    c.kind = first == "echo" ? Command::Kind::Echo : Command::Kind::Note;
    c.line = lineno;
    c.text = line;
    c.name = trim(line.substr(4));
    return c;
  }
  std::vector<std::string> t;
  const Words w{t, line, file, lineno};
  try {
    t = text::tokenize(line);
  } catch (const std::invalid_argument& e) {
    throw w.fail(e.what());
  }
  if (t.empty()) throw w.fail("empty command");
  Command c;
  c.line = lineno;
  c.text = line;
  for (const Verb& v : kVerbs)
    if (w.verb() == v.name) {
      v.parse(w, c);
      return c;
    }
  throw w.fail(fmt::format("unknown command '{}'; commands: set get params ref run start stop hold neutral resume "
                           "wait expect export echo note sweep tune ident",
                           w.verb()));
}

Script parse_script(const std::string& text, const std::string& file) {
  Script s;
  s.file = file;
  std::istringstream in(text);
  std::string line;
  int lineno = 0;
  std::vector<ScriptError> errors;
  while (std::getline(in, line)) {
    ++lineno;
    const std::string tl = trim(line);
    if (tl.empty() || tl[0] == '#') continue;
    try {
      s.commands.push_back(parse_command(tl, file, lineno));
    } catch (const ScriptError& e) {
      errors.push_back(e);
    }
  }
  if (!errors.empty()) throw ScriptError(errors);
  return s;
}

Script parse_script_file(const std::string& path) {
  std::string text;
  try {
    text = read_input_file(path, kScriptFile);
  } catch (const CliError& e) {
    // "PATH:0: cannot read script: …", the path said once.
    std::string what = e.what();
    for (const std::string& lead : {path + ": ", "cannot read " + path + ": "})
      if (what.rfind(lead, 0) == 0) what = "cannot read script: " + what.substr(lead.size());
    if (what.rfind("cannot read script: cannot read script: ", 0) == 0) what = what.substr(20);
    throw ScriptError(path, 0, what);
  }
  return parse_script(text, path);
}

const std::vector<std::string>& script_help() {
  static const std::vector<std::string> h = [] {
    std::vector<std::string> lines = {
      "set NAME VALUES...          set a parameter (all elements), or one: set Q[1] 2e6",
      "get NAME                    print a parameter's value in force",
      "params save FILE            write every parameter to FILE",
      "params load FILE            show the diff and apply it (all or nothing)",
      "params reapply              send this session's edits again (after a firmware reset)",
      "params diff                 what differs from the values the firmware boots with",
      "params reset                put every parameter back to those values (all or nothing)",
      "ref NAME key=value...       infinity|pringle|diagonal|swirl|steps|hold; keys a b c c0 c1 c2 period omega lambda scale hold levels",
      "ref load FILE.csv [hold=N]  upload a table of points and select it",
      "model upload FILE.nlsm      send a new forward model (not during a run); its hash is checked",
      "run DURATION [label=TEXT]   record a run, e.g. run 10s label=baseline; a run that ends",
      "                            before DURATION fails the script unless early=ok is given",
      "start [label=TEXT] | stop   start or stop a run without a duration",
      "ident SIGNAL DURATION ...   an identification run: steps|prbs|walk|chirp|aprbs, e.g. ident prbs 10min seed=3",
      "                            [amplitude=F] [band=LO:HI] [joint|mixed] [decimation=N] [label=TEXT] [early=ok]",
      "hold | neutral | resume     pause the run, actuators to neutral, continue",
      "wait DURATION               sleep, e.g. wait 500ms",
      "expect METRIC OP VALUE      check the last run, e.g. expect nrmse < 0.05, expect lost_frames == 0;",
      "                            fails on a run with lost samples unless lost=ok is given;",
      "                            nrmse_space (over the rig's task space) also for holds and steps",
      "export csv FILE             the last run's samples as CSV",
      "echo TEXT                   print TEXT",
      "note TEXT                   attach notes to the current (or last) run",
      "devices                     how each sensor chip answers the firmware (as rig check)",
      "settings save|defaults|report  keep the parameters in force across a reset (the firmware's flash),",
      "                            put the built-in ones back, or say where the ones in force came from",
      "sweep PARAM V1 V2 ... run D run once per value and print a table of metrics; each row",
      "  [settle=DURATION]         restarts the reference from its first point with the actuators",
      "                            neutral, and is measured after settle (default 1s)",
    };
    for (const std::string& l : tune_help()) lines.push_back(l);
    return lines;
  }();
  return h;
}

}  // namespace nlsoft::console
