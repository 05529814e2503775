#include "app/tune/objective.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace nlsoft::console {

struct Objective::Node {
  char op = 0;  // 0: number, 'm': metric, '~': negation, else + - * /
  double value = 0;
  std::string metric;
  std::shared_ptr<const Node> a, b;
};

namespace {

using NodeP = std::shared_ptr<const Objective::Node>;

// Recursive descent over: expr = term {(+|-) term}; term = unary {(*|/) unary};
// unary = - unary | primary; primary = number | metric | ( expr ).
class Parser {
 public:
  Parser(const std::string& text, std::vector<std::string>& metrics) : t_(text), metrics_(metrics) {}

  NodeP parse() {
    skip();
    if (i_ == t_.size()) throw ObjectiveError("the objective is empty; e.g. \"nrmse + 0.1*u_effort\"");
    NodeP n = expr();
    skip();
    if (i_ < t_.size()) fail(fmt::format("unexpected '{}'", t_[i_]));
    return n;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw ObjectiveError(fmt::format("objective \"{}\": {} at column {}", t_, what, i_ + 1));
  }
  void skip() {
    while (i_ < t_.size() && std::isspace(static_cast<unsigned char>(t_[i_]))) ++i_;
  }
  static NodeP binary(char op, NodeP a, NodeP b) {
    auto n = std::make_shared<Objective::Node>();
    n->op = op;
    n->a = std::move(a);
    n->b = std::move(b);
    return n;
  }
  NodeP expr() {
    NodeP n = term();
    while (true) {
      skip();
      if (i_ < t_.size() && (t_[i_] == '+' || t_[i_] == '-')) {
        const char op = t_[i_++];
        n = binary(op, n, term());
      } else {
        return n;
      }
    }
  }
  NodeP term() {
    NodeP n = unary();
    while (true) {
      skip();
      if (i_ < t_.size() && (t_[i_] == '*' || t_[i_] == '/')) {
        const char op = t_[i_++];
        n = binary(op, n, unary());
      } else {
        return n;
      }
    }
  }
  NodeP unary() {
    skip();
    if (i_ < t_.size() && t_[i_] == '-') {
      ++i_;
      return binary('~', unary(), nullptr);
    }
    if (i_ < t_.size() && t_[i_] == '+') {
      ++i_;
      return unary();
    }
    return primary();
  }
  NodeP primary() {
    skip();
    if (i_ >= t_.size()) fail("expected a number, a metric or '(' but the expression ended");
    const char c = t_[i_];
    if (c == '(') {
      ++i_;
      NodeP n = expr();
      skip();
      if (i_ >= t_.size() || t_[i_] != ')') fail("expected ')'");
      ++i_;
      return n;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      char* end = nullptr;
      const double v = std::strtod(t_.c_str() + i_, &end);
      if (end == t_.c_str() + i_ || !std::isfinite(v)) fail("bad number");
      i_ = size_t(end - t_.c_str());
      auto n = std::make_shared<Objective::Node>();
      n->value = v;
      return n;
    }
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      const size_t start = i_;
      while (i_ < t_.size() && (std::isalnum(static_cast<unsigned char>(t_[i_])) || t_[i_] == '_')) ++i_;
      const std::string name = t_.substr(start, i_ - start);
      if (!known_metric(name)) {
        i_ = start;
        std::string known;
        for (const auto& m : metric_names()) known += (known.empty() ? "" : ", ") + m;
        fail(fmt::format("unknown metric '{}' (known: {})", name, known));
      }
      bool seen = false;
      for (const auto& m : metrics_) seen |= m == name;
      if (!seen) metrics_.push_back(name);
      auto n = std::make_shared<Objective::Node>();
      n->op = 'm';
      n->metric = name;
      return n;
    }
    fail(fmt::format("expected a number, a metric or '(' but found '{}'", c));
  }

  const std::string& t_;
  std::vector<std::string>& metrics_;
  size_t i_ = 0;
};

double eval(const Objective::Node& n, const RunMetrics& m) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  switch (n.op) {
    case 0: return n.value;
    case 'm': return metric_value(m, n.metric).value_or(nan);
    case '~': return -eval(*n.a, m);
    case '+': return eval(*n.a, m) + eval(*n.b, m);
    case '-': return eval(*n.a, m) - eval(*n.b, m);
    case '*': return eval(*n.a, m) * eval(*n.b, m);
    case '/': return eval(*n.a, m) / eval(*n.b, m);
  }
  return nan;
}

}  // namespace

Objective::Objective(const std::string& text) : text_(text) { root_ = Parser(text_, metrics_).parse(); }
Objective::~Objective() = default;
Objective::Objective(const Objective&) = default;
Objective& Objective::operator=(const Objective&) = default;

double Objective::operator()(const RunMetrics& m) const {
  const double v = eval(*root_, m);
  return std::isfinite(v) ? v : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace nlsoft::console
