#include "app/model/progress.hpp"

#include <unistd.h>

#include <string>

namespace nlsoft::pipeline {

TrainProgress::TrainProgress(std::FILE* out) : out_(out), tty_(isatty(fileno(out)) != 0) {}

void TrainProgress::operator()(const Progress& p) {
  if (p.epochs == 0) {  // closed-form fit, no epochs
    std::fprintf(out_, "least-squares fit: validation loss %.3e\n", p.val_loss);
    return;
  }
  if (tty_) {
    const int width = 24;
    const int filled = static_cast<int>(width * static_cast<double>(p.epoch) / p.epochs);
    std::fprintf(out_, "\r[%s%s] epoch %d/%d  loss %.3e  val %.3e  best %.3e  ETA %.0fs \033[K",
                 std::string(size_t(filled), '#').c_str(), std::string(size_t(width - filled), '.').c_str(), p.epoch,
                 p.epochs, p.train_loss, p.val_loss, p.best_val, p.eta_s);
    std::fflush(out_);
    drawn_ = true;
  } else if (p.epoch == 1 || p.epoch % 10 == 0 || p.epoch == p.epochs) {
    std::fprintf(out_, "epoch %d/%d loss %.4e val %.4e best %.4e lr %.2e elapsed %.1fs\n", p.epoch, p.epochs,
                 p.train_loss, p.val_loss, p.best_val, p.lr, p.elapsed_s);
  }
}

void TrainProgress::finish() {
  if (drawn_) std::fprintf(out_, "\n");
  drawn_ = false;
}

}  // namespace nlsoft::pipeline
