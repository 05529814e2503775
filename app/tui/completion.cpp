#include "app/tui/completion.hpp"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "app/live/ident_plan.hpp"
#include "app/live/param_text.hpp"

namespace nlsoft::console::tui {

namespace {

const std::vector<std::string>& commands() {
  static const std::vector<std::string> c = {"set",  "get",    "params", "ref",  "run",    "start", "stop",
                                             "hold", "neutral", "resume", "wait", "expect", "export", "echo",
                                             "note", "devices", "settings", "sweep",  "tune",   "ident",  "plot",   "overlay", "model", "help", "quit"};
  return c;
}

std::vector<std::string> words_of(const std::string& line) {
  std::vector<std::string> w;
  std::string cur;
  for (char c : line) {
    if (c == ' ') {
      if (!cur.empty()) w.push_back(cur), cur.clear();
    } else {
      cur += c;
    }
  }
  w.push_back(cur);  // the word being typed, maybe empty
  return w;
}

// Entries of the folder the word names, as the word would spell them
// (folders end in '/', so Tab goes on into them). Hidden files only when
// the word starts with a dot, as in a shell.
std::vector<std::string> paths_for(const std::string& word) {
  namespace fs = std::filesystem;
  const size_t slash = word.rfind('/');
  const std::string dir = slash == std::string::npos ? "" : word.substr(0, slash + 1);
  const std::string base = slash == std::string::npos ? word : word.substr(slash + 1);
  std::vector<std::string> out;
  std::error_code ec;
  for (fs::directory_iterator it(dir.empty() ? "." : dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name[0] == '.' && (base.empty() || base[0] != '.')) continue;
    out.push_back(dir + name + (it->is_directory(ec) ? "/" : ""));
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

Completion complete_command(const std::string& line, const std::vector<std::string>& params) {
  const std::vector<std::string> w = words_of(line);
  const std::string& word = w.back();
  std::vector<std::string> pool;
  if (w.size() == 1) {
    pool = commands();
  } else if (w.size() == 2 && (w[0] == "set" || w[0] == "get" || w[0] == "sweep")) {
    pool = params;
  } else if (w.size() == 3 && w[0] == "set") {
    for (const ParamOption& o : param_options(w[1])) pool.push_back(o.name);
  } else if (w.size() == 2 && w[0] == "plot") {
    pool = {"y", "u", "cost", "iter", "compute", "ident"};
  } else if (w.size() == 2 && w[0] == "ident") {
    pool = kIdentSignals;
  } else if (w.size() >= 4 && w[0] == "ident") {
    // y_from= then a file: the file name completes after the '='.
    if (word.rfind("y_from=", 0) == 0) {
      for (const std::string& f : paths_for(word.substr(7))) pool.push_back("y_from=" + f);
    } else {
      pool = {"seed=", "amplitude=", "band=", "joint", "mixed", "decimation=", "label=", "early=ok", "y_from=", "y_offset="};
    }
  } else if (w.size() == 2 && w[0] == "ref") {
    pool = {"infinity", "pringle", "diagonal", "swirl", "steps", "hold", "load"};
  } else if (w.size() == 2 && w[0] == "params") {
    pool = {"save", "load", "reapply", "diff", "reset"};
  } else if (w.size() == 2 && w[0] == "settings") {
    pool = {"save", "defaults", "report"};
  } else if (w.size() == 2 && w[0] == "model") {
    pool = {"upload"};
  } else if (w.size() == 3 && ((w[0] == "model" && w[1] == "upload") || (w[0] == "ref" && w[1] == "load") ||
                               (w[0] == "params" && (w[1] == "save" || w[1] == "load")) ||
                               (w[0] == "export" && w[1] == "csv"))) {
    pool = paths_for(word);
  }
  Completion c;
  for (const std::string& p : pool)
    if (p.compare(0, word.size(), word) == 0) c.candidates.push_back(p);
  c.text = line;
  if (c.candidates.empty()) return c;
  // The longest prefix every candidate shares; a single one is finished
  // with a blank, ready for the next word.
  std::string common = c.candidates[0];
  for (const std::string& s : c.candidates) {
    size_t i = 0;
    while (i < common.size() && i < s.size() && common[i] == s[i]) ++i;
    common.resize(i);
  }
  c.text = line.substr(0, line.size() - word.size()) + common;
  if (c.candidates.size() == 1) {
    // A folder or a key= goes on being typed: no blank after those.
    if (common.empty() || (common.back() != '/' && common.back() != '=')) c.text += ' ';
    c.candidates.clear();
  }
  return c;
}

}  // namespace nlsoft::console::tui
