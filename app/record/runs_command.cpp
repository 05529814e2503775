#include "app/record/runs_command.hpp"

#include <fmt/format.h>

#include <strings.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <sstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "host/files/cli_error.hpp"
#include "host/files/output_file.hpp"
#include "host/files/printable.hpp"
#include "host/rig/rig_catalog.hpp"
#include "app/record/csv_export.hpp"
#include "app/record/h5_export.hpp"
#include "app/record/end_words.hpp"
#include "app/record/gnuplot.hpp"
#include "app/record/lock_gap.hpp"
#include "app/record/merge_y.hpp"
#include "app/record/loop_rate.hpp"
#include "app/record/run_plot.hpp"
#include "app/record/recorder.hpp"
#include "app/record/run_edit.hpp"
#include "app/record/run_metrics.hpp"
#include "app/record/run_store.hpp"
#include "app/record/tune_log.hpp"
#include "app/record/utc_time.hpp"
#include "app/text/duration.hpp"
#include "host/rig/rig_option.hpp"

namespace nlsoft::console {

using host::CliError;
using host::OutputFile;
using host::Rig;
using host::RigOutput;
using host::add_rig_option;
using host::load_rig_arg;
using host::printable;

namespace {

struct RunsArgs {
  std::string db;
  int64_t id = 0, other = 0;
  int64_t last = 0;          // runs list --last N
  std::string since, match;  // runs list --since WHEN, --label TEXT
  std::vector<int64_t> ids;
  int64_t tune = 0;  // runs plot --tune S
  std::string csv, h5, svg, png, label;
  bool json = false, force = false;
  std::string capture, rig;  // runs merge-y FILE.csv [--rig FILE]; runs export --h5 FILE [--rig FILE]
  std::optional<double> offset;
};

std::unique_ptr<RunStore> open_store(const RunsArgs& a) {
  try {
    return std::make_unique<RunStore>(a.db.empty() ? default_db_path() : a.db);
  } catch (const DbError& e) {
    throw CliError(e.what());
  }
}

// Draws a.ids (one run, or two overlaid) to a.svg or a.png with gnuplot.
void draw(const RunsArgs& a);

std::string rmse_list(const TrackingMetrics& t) {
  std::string s;
  for (double r : t.rmse) s += (s.empty() ? "" : " ") + fmt::format("{:.4g}", r);
  return "[" + s + "]";
}

nlohmann::json metrics_json(const RunRow& r, const RunMetrics& m) {
  const TrackingMetrics& t = m.has_true ? m.truth : m.predicted;
  nlohmann::json j;
  j["id"] = r.id;
  j["label"] = r.label;
  j["started_at"] = r.started_at;
  j["platform"] = r.platform;
  j["firmware"] = r.firmware;
  j["samples"] = m.samples;
  j["duration_s"] = m.duration_s;
  j["tracking_signal"] = m.has_true ? "y_true" : "y_hat";
  j["measured_output"] = m.has_true;
  j["tracked_axes"] = t.tracked;
  j["nrmse_all_axes"] = t.nrmse_all;
  j["rmse"] = t.rmse;
  j["nrmse"] = t.nrmse;
  j["nrmse_space"] = std::isfinite(m.nrmse_space) ? nlohmann::json(m.nrmse_space) : nlohmann::json();
  j["max_error"] = t.max_error;
  j["rmse_hat"] = m.predicted.rmse;
  j["nrmse_hat"] = m.predicted.nrmse;
  j["loop_rate_hz"] = m.loop_rate_hz;
  j["loop_rate_set_hz"] = m.loop_rate_set_hz;
  j["compute_p50_us"] = m.compute_p50_us;
  j["compute_p99_us"] = m.compute_p99_us;
  j["iterations"] = m.mean_iterations;
  j["lost_frames"] = m.lost_frames;
  j["gaps"] = m.gaps;
  j["wall_s"] = m.wall_s;
  j["u_effort"] = m.u_effort;
  j["u_saturated"] = m.u_saturated;
  // An identification run has no reference: no tracking figure, not a 0.
  if (r.kind == "ident")
    for (const char* k : {"tracked_axes", "nrmse_all_axes", "rmse", "nrmse", "nrmse_space", "max_error", "rmse_hat",
                          "nrmse_hat", "iterations"})
      j[k] = nullptr;
  return j;
}

// An identification run tracks nothing: only its loop, samples and losses.
void print_metrics(const RunMetrics& m, bool ident) {
  const TrackingMetrics& t = m.has_true ? m.truth : m.predicted;
  // Before any figure: what the tracking figures are (and are not) of.
  if (!m.has_true && m.samples > 0)
    fmt::print("  {}\n", ident ? "no measured output (y_true): nothing to train a model from until one is merged "
                                 "(runs merge-y ID FILE.csv)"
                               : kNoMeasuredOutput);
  if (ident) {
    fmt::print("  {}\n", loop_rate_text(m));
  } else {
    fmt::print("  tracking ({}): rmse {} nrmse {} max error {:.4g}\n", m.has_true ? "true plant" : "model prediction",
               rmse_list(t), nrmse_words(t.nrmse, true), t.max_error);
    fmt::print("  nrmse_space {:.4f} (worst axis over the rig's task space; defined for holds and steps)\n", m.nrmse_space);
    if (m.has_true) fmt::print("  prediction: rmse {} nrmse {}\n", rmse_list(m.predicted), nrmse_words(m.predicted.nrmse));
    fmt::print("  {}, compute p50 {:.1f} us p99 {:.1f} us, {:.2f} NR iterations\n", loop_rate_text(m), m.compute_p50_us,
               m.compute_p99_us, m.mean_iterations);
  }
  if (const std::string w = loop_rate_warning(m); !w.empty()) fmt::print("  {}\n", w);
  fmt::print("  {} samples over {:.2f} s{}, {} lost frame{}, {} gap{}\n", m.samples, m.duration_s,
             m.wall_s > 0 ? fmt::format(" (the run lasted {:.2f} s)", m.wall_s) : "", m.lost_frames,
             m.lost_frames == 1 ? "" : "s", m.gaps, m.gaps == 1 ? "" : "s");
}

// "gap after sample 383: 351 frames lost (2.7 s at 130 Hz); telemetry
// silent for 3.00 s". The frames are the steps that never arrived, at the
// run's telemetry rate; the silence is how long nothing came (before the
// run gave up, for a run that ended early): two different times, each named
// for what it is.
std::string gap_words(const RunRow& r, const GapRecord& g) {
  std::string s = fmt::format("gap after sample {}: {} frame{} lost", g.after_k, g.lost_frames, g.lost_frames == 1 ? "" : "s");
  const double rate = r.loop_rate_hz / double(r.decimation > 0 ? r.decimation : 1);
  if (rate > 0) s += fmt::format(" ({:.1f} s at {:g} Hz)", double(g.lost_frames) / rate, rate);
  // Samples lost to a database lock arrived all the same: their time is
  // what they span, not a silence.
  if (g.duration_s >= 0)
    s += is_lock_gap(g.reason) ? fmt::format("; the samples lost span {:.2f} s", g.duration_s)
                               : fmt::format("; telemetry silent for {:.2f} s", g.duration_s);
  return s;
}

// "swirl", "table", ...: the kind of the run's reference at its start.
std::string reference_kind(const std::string& json) {
  if (json.empty()) return "-";
  const auto j = nlohmann::json::parse(json, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("kind") || !j["kind"].is_string()) return "?";
  return j["kind"].get<std::string>();
}

// The reference a run started with, or, when it started without one, the
// first one sent during it (logged as a `reference` change).
std::string reference_of(RunStore& store, const RunRow& r) {
  if (!r.reference.empty()) return r.reference;
  for (const ParamRecord& p : store.params(r.id))
    if (!p.at_start && p.name == "reference") return p.value;
  return "";
}

// --since: a date ("2026-11-25", "2026-11-25T10:30", seconds optional) or
// a time back from now ("90min", "2h", "3d"), as the ISO text the runs'
// start times are stored in, which compares as text.
std::string since_text(const std::string& since) {
  int y = 0, mo = 0, d = 0, h = 0, mi = 0, sec = 0, used = 0;
  const char* c = since.c_str();
  if (std::sscanf(c, "%4d-%2d-%2d%n", &y, &mo, &d, &used) == 3 && used == 10) {
    const std::string rest = since.substr(10);
    int more = 0;
    const bool ok = rest.empty() ||
                    ((rest[0] == 'T' || rest[0] == ' ') &&
                     ((std::sscanf(rest.c_str() + 1, "%2d:%2d:%2d%n", &h, &mi, &sec, &more) == 3 &&
                       size_t(more) + 1 == rest.size()) ||
                      (std::sscanf(rest.c_str() + 1, "%2d:%2d%n", &h, &mi, &more) == 2 && size_t(more) + 1 == rest.size())));
    if (ok && mo >= 1 && mo <= 12 && d >= 1 && d <= 31 && h < 24 && mi < 60 && sec < 61)
      return fmt::format("{:04d}-{:02d}-{:02d}T{:02d}:{:02d}:{:02d}.000Z", y, mo, d, h, mi, sec);
  } else {
    char* end = nullptr;
    const double v = std::strtod(c, &end);
    const std::string unit = end ? end : "";
    double back_s = -1;
    if (end != c && v > 0 && (unit == "d" || unit == "days" || unit == "day")) back_s = v * 86400;
    else if (end != c && v > 0 && (unit == "w" || unit == "weeks" || unit == "week")) back_s = v * 7 * 86400;
    else {
      try {
        back_s = text::parse_duration(since);
      } catch (const std::invalid_argument&) {
      }
    }
    if (back_s > 0) {
      const auto now = utc_seconds(utc_now());
      const time_t t = time_t(std::floor((now ? *now : double(std::time(nullptr))) - back_s));
      tm u{};
      gmtime_r(&t, &u);
      char buf[40];
      std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S.000Z", &u);
      return buf;
    }
  }
  throw CliError(fmt::format("runs list --since '{}': give a date (2026-11-25, 2026-11-25T10:30, UTC) or a time back "
                             "from now (90min, 2h, 3d)", since));
}

// The runs --last, --label and --since leave, in id order.
std::vector<RunRow> chosen_runs(const RunsArgs& a, std::vector<RunRow> runs) {
  if (!a.match.empty())
    runs.erase(std::remove_if(runs.begin(), runs.end(),
                              [&](const RunRow& r) {
                                return std::search(r.label.begin(), r.label.end(), a.match.begin(), a.match.end(),
                                                   [](char x, char y) { return std::tolower(x) == std::tolower(y); }) ==
                                       r.label.end();
                              }),
               runs.end());
  if (!a.since.empty()) {
    const std::string from = since_text(a.since);
    runs.erase(std::remove_if(runs.begin(), runs.end(), [&](const RunRow& r) { return r.started_at < from; }),
               runs.end());
  }
  if (a.last > 0 && runs.size() > size_t(a.last)) runs.erase(runs.begin(), runs.end() - a.last);
  return runs;
}

// The runs of the tuning sessions: each run's evaluation, each session's
// runs in order, and the sessions.
struct TuneIndex {
  std::map<int64_t, TuneEvalRow> eval_of;
  std::map<int64_t, std::vector<int64_t>> session_runs;
  std::map<int64_t, TuneSessionRow> sessions;
};

TuneIndex tune_index(const std::string& path) {
  TuneIndex t;
  for (const TuneSessionRow& s : tune_sessions(path)) {
    t.sessions[s.id] = s;
    for (const TuneEvalRow& e : tune_evals(path, s.id)) {
      t.eval_of[e.run_id] = e;
      t.session_runs[s.id].push_back(e.run_id);
    }
  }
  return t;
}

// `runs list --json`: one object per run, a tuning evaluation's with its session.
void list_json(RunStore& store, const std::vector<RunRow>& runs, const std::map<int64_t, TuneEvalRow>& eval_of) {
  nlohmann::json out = nlohmann::json::array();
  for (const RunRow& r : runs) {
    const RunMetrics m = run_metrics(store, r.id);
    const TrackingMetrics& t = m.has_true ? m.truth : m.predicted;
    nlohmann::json j = {{"id", r.id},           {"started_at", r.started_at}, {"platform", r.platform},
                        {"label", r.label},     {"samples", r.samples},       {"lost_frames", r.lost_frames},
                        {"ended_at", r.ended_at}, {"end_reason", r.end_reason}};
    const std::string ref = reference_of(store, r);
    j["reference"] = ref.empty() ? nlohmann::json() : nlohmann::json::parse(ref, nullptr, false);
    j["kind"] = r.kind;
    if (!r.excitation.empty()) j["excitation"] = nlohmann::json::parse(r.excitation, nullptr, false);
    j["nrmse"] = std::isfinite(t.nrmse) && r.kind != "ident" ? nlohmann::json(t.nrmse) : nlohmann::json();
    j["measured_output"] = m.has_true;
    if (const auto e = eval_of.find(r.id); e != eval_of.end()) {
      nlohmann::json tj = {{"session", e->second.session_id}, {"eval", e->second.eval}, {"point", e->second.point}};
      tj["objective"] = e->second.objective ? nlohmann::json(*e->second.objective) : nlohmann::json();
      if (!e->second.failed.empty()) tj["failed"] = e->second.failed;
      j["tune"] = tj;
    }
    out.push_back(j);
  }
  fmt::print("{}\n", out.dump(2));
}

void list(const RunsArgs& a) {
  auto store = open_store(a);
  const auto all_runs = store->list();
  const auto runs = chosen_runs(a, all_runs);
  const bool filtered = !a.match.empty() || !a.since.empty() || a.last > 0;
  const std::string path = a.db.empty() ? default_db_path() : a.db;
  TuneIndex tune = tune_index(path);
  std::map<int64_t, TuneEvalRow>& eval_of = tune.eval_of;
  std::map<int64_t, std::vector<int64_t>>& session_runs = tune.session_runs;
  std::map<int64_t, TuneSessionRow>& sessions = tune.sessions;
  if (a.json) {
    list_json(*store, runs, eval_of);
    return;
  }
  if (runs.empty()) {
    if (filtered && !all_runs.empty())
      fmt::print("none of the {} runs in {} matches{}{}{}\n", all_runs.size(), path,
                 a.match.empty() ? "" : fmt::format(" --label '{}'", a.match),
                 a.since.empty() ? "" : fmt::format(" --since {}", a.since),
                 a.last > 0 ? fmt::format(" --last {}", a.last) : "");
    else
      fmt::print("no runs recorded yet in {}\n", path);
    return;
  }
  // Every run read before a line is printed: a run the file holds damaged
  // is refused in one sentence, not after half a table.
  std::map<int64_t, RunMetrics> metrics;
  for (const RunRow& r : runs) metrics.emplace(r.id, run_metrics(*store, r.id));
  fmt::print("{:>5}  {:<20} {:<7} {:<9} {:>9} {:>10} {:>6}  {:<20} {}\n", "id", "started (UTC)", "rig", "reference",
             "samples", "nrmse(run)", "lost", "label", "ended");
  std::map<int64_t, const RunRow*> by_id;  // the runs shown
  for (const RunRow& r : runs) by_id[r.id] = &r;
  bool any_predicted = false;  // a control run's nrmse scored on y_hat: marked '*'
  auto line = [&](const RunRow& r, const std::string& indent, const std::string& ended) {
    const RunMetrics& m = metrics.at(r.id);
    const TrackingMetrics& t = m.has_true ? m.truth : m.predicted;
    const bool predicted = !m.has_true && m.samples > 0 && std::isfinite(t.nrmse) && r.kind != "ident";
    any_predicted = any_predicted || predicted;
    // Every text column is the file's: escaped, as in `runs show`.
    fmt::print("{:>5}  {}{:<20} {:<7} {:<9} {:>9} {:>10} {:>6}  {:<20} {}\n", r.id, indent,
               printable(r.started_at.substr(0, 19)), printable(r.platform),
               r.kind == "ident" ? std::string("ident") : printable(reference_kind(reference_of(*store, r))), r.samples,
               m.samples > 0 && std::isfinite(t.nrmse) && r.kind != "ident"
                   ? fmt::format("{:.4f}{}", t.nrmse, predicted ? "*" : "")
                   : "-",
               r.lost_frames,
               printable(r.label), printable(ended));
  };
  // The runs of a tuning session: its header goes before its first run, its
  // evaluations follow indented with their objective, and a session's later
  // runs stay with it even when other runs came between.
  bool any_eval = false;
  for (const RunRow& r : runs) {
    const auto e = eval_of.find(r.id);
    if (e == eval_of.end()) {
      line(r, "", end_words(r.ended_at, r.end_reason));
      continue;
    }
    any_eval = true;
    std::vector<int64_t> members;  // the session's runs this listing shows
    for (int64_t id : session_runs[e->second.session_id])
      if (by_id.count(id)) members.push_back(id);
    if (members.front() != r.id) continue;  // printed with its session
    const TuneSessionRow& s = sessions[e->second.session_id];
    fmt::print("tuning session {}: minimise {} over {} ({}), {} evaluation{}, {}{}\n", s.id, printable(s.objective),
               printable(s.space), printable(s.method), members.size(), members.size() == 1 ? "" : "s",
               s.ended_at.empty() ? "unfinished" : printable(s.end_reason),
               s.best_run > 0 ? fmt::format("; best run {}", s.best_run) : "");
    for (int64_t id : members) {
      const auto row = by_id.find(id);
      if (row == by_id.end()) continue;  // deleted
      const TuneEvalRow& ev = eval_of[id];
      line(*row->second, "  ",
           ev.objective ? fmt::format("objective {:.5g}{}", *ev.objective, id == s.best_run ? " (best)" : "")
                        : "failed: " + failure_words(ev.failed));
    }
  }
  // What the two columns that invite questions hold.
  fmt::print("nrmse(run): over the whole recorded run{}; ended: in a word, runs show ID says why in full\n",
             any_eval ? ", where a tuning evaluation's objective is scored over its window after the settle: the "
                        "two differ"
                      : "");
  if (any_predicted) fmt::print("*: {}\n", kNoMeasuredOutput);
}

void show(const RunsArgs& a) {
  auto store = open_store(a);
  const RunRow r = store->run(a.id);
  const RunMetrics m = run_metrics(*store, a.id);
  if (a.json) {
    nlohmann::json j = metrics_json(r, m);
    nlohmann::json params = nlohmann::json::object(), changes = nlohmann::json::array();
    for (const auto& p : store->params(a.id)) {
      if (p.at_start) params[p.name] = p.value;
      else changes.push_back({{"t", p.t}, {"name", p.name}, {"value", p.value}});
    }
    j["params"] = params;
    j["param_changes"] = changes;
    nlohmann::json gaps = nlohmann::json::array();
    for (const auto& g : store->gaps(a.id)) {
      nlohmann::json x = {{"after_k", g.after_k}, {"lost_frames", g.lost_frames}, {"reason", g.reason}, {"t", g.t}};
      x["duration_s"] = g.duration_s >= 0 ? nlohmann::json(g.duration_s) : nlohmann::json();
      gaps.push_back(x);
    }
    j["gap_list"] = gaps;
    j["reference"] = r.reference.empty() ? nlohmann::json() : nlohmann::json::parse(r.reference, nullptr, false);
    j["kind"] = r.kind;
    j["w"] = r.w;
    if (!r.excitation.empty()) j["excitation"] = nlohmann::json::parse(r.excitation, nullptr, false);
    fmt::print("{}\n", j.dump(2));
    return;
  }
  // Everything read from the file is shown escaped: a shared database is
  // anyone's text.
  fmt::print("run {}{}  {} .. {}  ({})\n", r.id, r.label.empty() ? "" : " \"" + printable(r.label) + "\"",
             printable(r.started_at), r.ended_at.empty() ? "?" : printable(r.ended_at),
             r.ended_at.empty() ? "unfinished: console stopped" : printable(r.end_reason));
  fmt::print("  {} on {}, model {:08x}, n={} m={}, nominal {:.0f} Hz, decimation {}\n", printable(r.firmware),
             printable(r.platform), r.model_hash, r.n, r.m, r.loop_rate_hz, r.decimation);
  if (!r.reference.empty()) fmt::print("  reference {}\n", printable(r.reference));
  if (r.kind == "ident")
    fmt::print("  identification run (open loop, u, measured y and {} sensors a sample): {}\n", r.w,
               printable(r.excitation));
  if (!r.notes.empty()) fmt::print("  notes: {}\n", printable(r.notes));
  print_metrics(m, r.kind == "ident");
  fmt::print("  parameters at start:\n");
  for (const auto& p : store->params(a.id))
    if (p.at_start) fmt::print("    {:<12} {}\n", printable(p.name), printable(p.value));
  for (const auto& p : store->params(a.id))
    if (!p.at_start) fmt::print("  at {:8.3f} s: {} = {}\n", p.t, printable(p.name), printable(p.value));
  for (const auto& g : store->gaps(a.id))
    fmt::print("  {} ({}, {})\n", gap_words(r, g), printable(g.reason), printable(g.t));
  for (const auto& [when, detail] : store->link_events(a.id))
    fmt::print("  link {}: {}\n", printable(when), printable(detail));
}

void export_runs(const RunsArgs& a) {
  if (!a.csv.empty() && !a.h5.empty()) throw CliError("runs export: give --csv FILE or --h5 FILE, not both");
  if (!a.rig.empty() && a.h5.empty())
    throw CliError("runs export --rig: a CSV keeps its columns y_true0.., u0..; the rig's names and units go into "
                   "HDF5 (--h5 FILE)");
  auto store = open_store(a);
  const std::string path = !a.h5.empty() ? a.h5 : a.csv.empty() ? "-" : a.csv;
  if (!a.h5.empty() && path == "-" && ::isatty(STDOUT_FILENO))
    throw CliError("runs export --h5 -: standard output is a terminal; name a file (--h5 runs.h5) or redirect it");
  H5Export h5;
  if (!a.h5.empty()) h5 = export_runs_h5(*store, a.ids, path, a.rig);
  const uint64_t rows = a.h5.empty() ? export_runs_csv(*store, a.ids, path) : h5.samples;
  std::string which = fmt::format("run {}", a.ids.front());
  if (a.ids.size() > 1) {
    which = "runs";
    for (size_t i = 0; i < a.ids.size(); ++i) which += fmt::format("{}{}", i ? ", " : " ", a.ids[i]);
  }
  // The file may be standard output: the report goes where it cannot mix in.
  fmt::print(stderr, "{}: {} samples written to {}{}\n", which, rows, path == "-" ? "standard output" : path,
             a.h5.empty() ? "" : " (HDF5)");
  if (!h5.unnamed.empty()) fmt::print(stderr, "{}\n", h5.unnamed);
}

// Two runs' values of one parameter, blank-separated elements padded so
// that element k of one sits above element k of the other.
std::vector<std::pair<int64_t, std::string>> aligned_columns(int64_t ida, const std::string& a, int64_t idb,
                                                             const std::string& b) {
  auto words = [](const std::string& text) {
    std::vector<std::string> w;
    std::istringstream in(text);
    for (std::string t; in >> t;) w.push_back(t);
    return w;
  };
  const std::vector<std::string> wa = words(a), wb = words(b);
  std::vector<size_t> width(std::max(wa.size(), wb.size()), 0);
  for (const auto* w : {&wa, &wb})
    for (size_t k = 0; k < w->size(); ++k) width[k] = std::max(width[k], (*w)[k].size());
  auto line = [&](const std::vector<std::string>& w) {
    std::string s;
    for (size_t k = 0; k < w.size(); ++k) s += fmt::format("{}{:>{}}", k ? "  " : "", w[k], width[k]);
    return s.empty() ? std::string("(none)") : s;
  };
  return {{ida, line(wa)}, {idb, line(wb)}};
}

void compare(const RunsArgs& a) {
  if (!a.svg.empty() && !a.png.empty()) throw CliError("runs compare: give --svg FILE or --png FILE, not both");
  if (!a.svg.empty() || !a.png.empty()) {
    RunsArgs both = a;
    both.ids = {a.id, a.other};
    draw(both);
  }
  auto store = open_store(a);
  const RunRow ra = store->run(a.id), rb = store->run(a.other);
  const RunMetrics ma = run_metrics(*store, a.id), mb = run_metrics(*store, a.other);
  std::map<std::string, std::pair<std::string, std::string>> pdiff;
  for (const auto& p : store->params(a.id))
    if (p.at_start) pdiff[p.name].first = p.value;
  for (const auto& p : store->params(a.other))
    if (p.at_start) pdiff[p.name].second = p.value;
  if (a.json) {
    nlohmann::json j;
    j["a"] = metrics_json(ra, ma);
    j["b"] = metrics_json(rb, mb);
    nlohmann::json d = nlohmann::json::object();
    for (const auto& [name, v] : pdiff)
      if (v.first != v.second) d[name] = {v.first, v.second};
    j["param_diff"] = d;
    fmt::print("{}\n", j.dump(2));
    return;
  }
  auto row = [](const char* name, const std::string& x, const std::string& y) {
    fmt::print("  {:<16} {:>24} {:>24}\n", name, x, y);
  };
  fmt::print("  {:<16} {:>24} {:>24}\n", "", fmt::format("run {}", ra.id), fmt::format("run {}", rb.id));
  row("label", printable(ra.label), printable(rb.label));
  row("platform", printable(ra.platform), printable(rb.platform));
  auto num = [](double v) { return fmt::format("{:.5g}", v); };
  for (const char* m : {"rmse", "nrmse", "max_error", "rmse_hat", "nrmse_hat", "u_effort", "u_saturated",
                        "loop_rate_hz", "compute_p50_us", "compute_p99_us", "iterations", "lost_frames", "gaps",
                        "samples", "duration_s"})
    row(m, num(metric_value(ma, m).value_or(0)), num(metric_value(mb, m).value_or(0)));
  bool any = false;
  for (const auto& [name, v] : pdiff) {
    if (v.first == v.second) continue;
    if (!any) fmt::print("  parameters that differ:\n");
    any = true;
    const std::string x = printable(v.first), y = printable(v.second);
    if (x.size() <= 24 && y.size() <= 24 && x.find(' ') == std::string::npos && y.find(' ') == std::string::npos) {
      row(printable(name).c_str(), x, y);
      continue;
    }
    // Vectors: one run per line, element under element.
    fmt::print("  {}\n", printable(name));
    for (const auto& [id, line] : aligned_columns(ra.id, x, rb.id, y)) fmt::print("    run {:<6} {}\n", id, line);
  }
  if (!any) fmt::print("  same parameters at start\n");
}

void plot(const RunsArgs& a) {
  if (a.svg.empty() == a.png.empty()) throw CliError("runs plot: give one of --svg FILE or --png FILE");
  if (a.tune > 0) {
    if (!a.ids.empty()) throw CliError("runs plot: give run ids or --tune SESSION, not both");
    open_store(a);  // the file's existence and schema, in the store's words
    const std::string path = a.db.empty() ? default_db_path() : a.db;
    const TuneSessionRow s = tune_session(path, a.tune);
    const bool svg = !a.svg.empty();
    const std::string image =
        run_gnuplot(tune_plot_script(s, tune_evals(path, a.tune), svg ? ImageFormat::Svg : ImageFormat::Png));
    const std::string& file = svg ? a.svg : a.png;
    OutputFile out(file);
    if (std::fwrite(image.data(), 1, image.size(), out.get()) != image.size())
      throw CliError(fmt::format("cannot write {}", file));
    out.commit();
    if (file != "-") fmt::print(stderr, "tuning session {} drawn to {}\n", a.tune, file);
    return;
  }
  if (a.ids.empty() || a.ids.size() > 2) throw CliError("runs plot: give one run id, two to overlay, or --tune SESSION");
  draw(a);
}

void draw(const RunsArgs& a) {
  auto store = open_store(a);
  std::vector<PlottedRun> runs;
  for (int64_t id : a.ids) runs.push_back(load_plotted_run(*store, id));
  const bool svg = !a.svg.empty();
  const std::string image = run_gnuplot(run_plot_script(runs, svg ? ImageFormat::Svg : ImageFormat::Png));
  const std::string& path = svg ? a.svg : a.png;
  OutputFile out(path);
  if (std::fwrite(image.data(), 1, image.size(), out.get()) != image.size())
    throw CliError(fmt::format("cannot write {}", path));
  out.commit();
  if (path != "-")
    fmt::print(stderr, "{} drawn to {}\n",
               a.ids.size() > 1 ? fmt::format("runs {} and {}", a.ids[0], a.ids[1]) : fmt::format("run {}", a.ids[0]),
               path);
}

// The rig's output names, accepted as the capture's column names: --rig's
// file, else the shipped rig the run names (none when neither is found).
std::vector<std::string> output_names(const RunsArgs& a, const RunRow& r) {
  std::vector<std::string> names;
  try {
    const Rig rig = load_rig_arg(a.rig.empty() ? r.platform : a.rig);
    if (rig.n() == r.n)
      for (const RigOutput& o : rig.outputs) names.push_back(o.name);
  } catch (const CliError&) {
    if (!a.rig.empty()) throw;
  }
  return names;
}

void merge_capture(const RunsArgs& a) {
  const std::string path = a.db.empty() ? default_db_path() : a.db;
  RunRow row;
  {
    auto store = open_store(a);
    row = store->run(a.id);
  }
  const MergeReport r = merge_y(path, a.id, a.capture, a.offset, output_names(a, row));
  fmt::print("{}\n", merge_words(a.id, a.capture, r));
}

}  // namespace

void compare_runs(const std::string& db, int64_t a, int64_t b, bool json, const std::string& svg,
                  const std::string& png) {
  RunsArgs args;
  args.db = db;
  args.id = a;
  args.other = b;
  args.json = json;
  args.svg = svg;
  args.png = png;
  compare(args);
}

namespace {

void add_db_option(CLI::App* c, const std::shared_ptr<RunsArgs>& args) {
  c->add_option("--db", args->db, "Recording database (default $XDG_DATA_HOME/nlsoft/runs.db)");
}

// runs list, runs show
void add_reading_commands(CLI::App* runs, const std::shared_ptr<RunsArgs>& args) {
  CLI::App* l = runs->add_subcommand(
      "list", "One line per run: rig, reference, samples, nRMSE over the run, lost frames, label, how it ended");
  add_db_option(l, args);
  l->add_flag("--json", args->json, "Machine-readable output: an array of runs");
  l->add_option("--last", args->last, "Only the last N runs (after the other filters)")->check(CLI::PositiveNumber);
  l->add_option("--label", args->match, "Only runs whose label contains TEXT (any case)");
  l->add_option("--since", args->since,
                "Only runs started since a date (2026-11-25, 2026-11-25T10:30, UTC) or a time back from now (2h, 3d)");
  l->callback([args] { list(*args); });
  CLI::App* s = runs->add_subcommand("show", "A run's setup, parameters, gaps and metrics");
  add_db_option(s, args);
  s->add_option("ID", args->id, "Run id (see runs list)")->required();
  s->add_flag("--json", args->json, "Machine-readable output");
  s->callback([args] { show(*args); });
}

// runs export, compare, plot
void add_output_commands(CLI::App* runs, const std::shared_ptr<RunsArgs>& args) {
  CLI::App* e = runs->add_subcommand(
      "export", "Runs' samples as CSV (one run, or several with a run column) or HDF5 (MATLAB h5read, Python h5py)");
  add_db_option(e, args);
  e->add_option("ID", args->ids, "Run ids")->required();
  e->add_option("--csv", args->csv, "CSV file ('-' or none: standard output)");
  e->add_option("--h5", args->h5,
                "HDF5 file: a group run_ID per run with t, u, y_ref, y_hat, y_true, cost, iterations as datasets with "
                "units; the run's rig, firmware, model hash and parameters as attributes; its gaps");
  add_rig_option(e, args->rig,
                "HDF5: the rig whose outputs', inputs' and sensors' names and units the runs' columns get "
                "(default: each run's rig when it is a shipped one); its n, m, w must be the runs'");
  e->callback([args] { export_runs(*args); });
  CLI::App* c = runs->add_subcommand("compare", "Two runs' metrics and parameter differences side by side");
  add_db_option(c, args);
  c->add_option("A", args->id, "First run id")->required();
  c->add_option("B", args->other, "Second run id")->required();
  c->add_flag("--json", args->json, "Machine-readable output");
  c->add_option("--svg", args->svg, "Also draw both runs overlaid, as runs plot A B does");
  c->add_option("--png", args->png, "Also draw both runs overlaid, as a PNG");
  c->callback([args] { compare(*args); });
  CLI::App* p = runs->add_subcommand(
      "plot", "Draw a run (or two overlaid): y per axis against the reference, u, the x-y path; needs gnuplot");
  add_db_option(p, args);
  p->add_option("ID", args->ids, "Run id; a second id overlays that run (dashed)")->expected(1, 2);
  p->add_option("--tune", args->tune, "A tuning session instead: its objective against the evaluation, best so far")
      ->check(CLI::PositiveNumber);
  p->add_option("--svg", args->svg, "Write an SVG image ('-': standard output)");
  p->add_option("--png", args->png, "Write a PNG image ('-': standard output)");
  p->callback([args] { plot(*args); });
}

// runs delete, merge-y, label
void add_editing_commands(CLI::App* runs, const std::shared_ptr<RunsArgs>& args) {
  CLI::App* d = runs->add_subcommand("delete", "Delete runs with their samples, parameters, gaps and link events");
  add_db_option(d, args);
  d->add_option("ID", args->ids, "Run ids (all are deleted, or none)")->required();
  d->add_flag("--force", args->force,
              "Delete an unfinished run too (one a killed console left open); a run a console is still recording "
              "is refused all the same");
  d->callback([args] {
    for (const std::string& note : delete_runs(args->db.empty() ? default_db_path() : args->db, args->ids, args->force))
      fmt::print(stderr, "{}\n", printable(note));
    for (int64_t id : args->ids) fmt::print("run {} deleted\n", id);  // in the order given
  });
  CLI::App* my = runs->add_subcommand(
      "merge-y", "Make an external measurement of the outputs (motion capture) a run's measured outputs, y_true");
  add_db_option(my, args);
  my->add_option("ID", args->id, "Run id")->required();
  my->add_option("FILE", args->capture,
                 "CSV with a header time,y0,y1,... (or the rig's output names), time in seconds on the capture's own "
                 "clock")
      ->required();
  my->add_option("--offset", args->offset,
                 "The capture clock's offset in seconds (run time = capture time - S); default: estimated from the "
                 "run's inputs and sensors");
  add_rig_option(my, args->rig, "The rig file whose output names the columns may carry (default: the run's rig)");
  my->footer(
      "The capture is interpolated linearly onto the run's samples (run time: the control step over the loop\n"
      "rate, from the run's first step); samples outside it keep no measured output. One transaction: a bad\n"
      "file (a missing or unknown column, a time out of order, NaN, no overlap) changes nothing, exit 2.\n");
  my->callback([args] { merge_capture(*args); });
  CLI::App* lb = runs->add_subcommand("label", "Give a run a new label");
  add_db_option(lb, args);
  lb->add_option("ID", args->id, "Run id")->required();
  lb->add_option("TEXT", args->label, "The label (quote it if it has blanks; \"\" clears it)")->required();
  lb->callback([args] {
    label_run(args->db.empty() ? default_db_path() : args->db, args->id, args->label);
    fmt::print("run {} labelled \"{}\"\n", args->id, printable(args->label));
  });
}

}  // namespace

void add_runs_command(CLI::App& app) {
  auto args = std::make_shared<RunsArgs>();
  CLI::App* runs = app.add_subcommand("runs", "Recorded runs: list, show, export, compare, plot, label, delete");
  runs->require_subcommand(1);
  runs->footer(
      "Examples:\n"
      "  nlsoft-console runs list\n"
      "  nlsoft-console runs list --last 5 --label baseline --since 2h\n"
      "  nlsoft-console runs show 12\n"
      "  nlsoft-console runs export 12 --csv run12.csv\n"
      "  nlsoft-console runs compare 12 13 --json\n"
      "  nlsoft-console runs compare 12 13 --svg compare.svg\n"
      "  nlsoft-console runs export 12 > run12.csv\n"
      "  nlsoft-console runs export 12 13 --h5 runs.h5\n"
      "  nlsoft-console runs plot 12 --svg run12.svg\n"
      "  nlsoft-console runs plot 12 13 --png compare.png\n"
      "  nlsoft-console runs label 12 \"Lambda 4, smoother\"\n"
      "  nlsoft-console runs merge-y 12 mocap.csv\n"
      "  nlsoft-console runs delete 12\n");
  add_db_option(runs, args);
  add_reading_commands(runs, args);
  add_output_commands(runs, args);
  add_editing_commands(runs, args);
}

}  // namespace nlsoft::console
