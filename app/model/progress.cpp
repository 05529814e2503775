#include "app/model/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace nlsoft::model {

TrainProgress::TrainProgress(std::FILE* out) : out_(out), tty_(isatty(fileno(out)) != 0) {}

std::string TrainProgress::eta(const Progress& p) {
  if (p.elapsed_s < last_elapsed_) done_.clear();  // a new training (the history search runs several)
  last_elapsed_ = p.elapsed_s;
  if (p.candidate < 0 || p.candidates < 1) return "";
  done_.resize(size_t(p.candidates), 0.0);
  const bool one_step = std::string(p.phase) == "one-step";
  const double within = p.epochs > 0 ? std::min(1.0, double(p.epoch) / p.epochs) : 1.0;
  // The one-step half often stops early (patience), so this overestimates.
  done_[size_t(p.candidate)] = std::max(done_[size_t(p.candidate)], one_step ? 0.5 * within : 0.5 + 0.5 * within);
  double f = 0;
  for (double d : done_) f += d;
  f /= double(done_.size());
  if (f < 0.02 || p.elapsed_s < 2.0) return "";
  const long left = std::lround(p.elapsed_s * (1.0 - f) / f);
  return left >= 60 ? "  ETA ~" + std::to_string(left / 60) + "m" + std::to_string(left % 60) + "s"
                    : "  ETA ~" + std::to_string(left) + "s";
}

void TrainProgress::operator()(const Progress& p) {
  const std::string left = eta(p);
  // Which of several candidates, when there are several.
  const std::string who =
      p.candidate < 0      ? std::string("start model ")
      : p.candidates > 1 ? "candidate " + std::to_string(p.candidate + 1) + "/" + std::to_string(p.candidates) + " "
                         : "";
  if (p.epochs == 0) {  // closed-form fit, no epochs
    if (tty_ && drawn_) std::fprintf(out_, "\r\033[K");
    std::fprintf(out_, "%sleast-squares warm start: one-step validation loss %.3e\n", who.c_str(), p.val_loss);
    drawn_ = false;
    return;
  }
  // One-step losses are in normalised output units; the simulation phases
  // report the validation rows' free run (variance-weighted MSE).
  const char* val = std::string(p.phase) == "one-step" ? "val" : "val free-run";
  const char* step = std::string(p.phase) == "L-BFGS" ? "eval" : "epoch";
  if (tty_) {
    const int width = 20;
    const int filled = static_cast<int>(width * std::min(1.0, static_cast<double>(p.epoch) / p.epochs));
    std::fprintf(out_, "\r%s%s [%s%s] %s %d/%d  loss %.3e  %s %.3e  best %.3e  %.0fs%s \033[K", who.c_str(), p.phase,
                 std::string(size_t(filled), '#').c_str(), std::string(size_t(width - filled), '.').c_str(), step,
                 p.epoch, p.epochs, p.train_loss, val, p.val_loss, p.best_val, p.elapsed_s, left.c_str());
    std::fflush(out_);
    drawn_ = true;
  } else if (p.epoch == 1 || p.epoch % 25 == 0 || p.epoch == p.epochs) {
    std::fprintf(out_, "%s%s %s %d/%d loss %.4e %s %.4e best %.4e elapsed %.1fs%s\n", who.c_str(), p.phase, step,
                 p.epoch, p.epochs, p.train_loss, val, p.val_loss, p.best_val, p.elapsed_s, left.c_str());
  }
}

// The bar is cleared, not left half-drawn: what training ended with is in
// the lines printed after it.
void TrainProgress::finish() {
  if (drawn_) std::fprintf(out_, "\r\033[K");
  std::fflush(out_);
  drawn_ = false;
}

}  // namespace nlsoft::model
