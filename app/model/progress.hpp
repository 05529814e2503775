#pragma once
// Training progress for humans: a redrawn one-line bar with loss and ETA on a
// terminal, a plain line every few epochs otherwise (logs, CI).
#include <cstdio>
#include <string>
#include <vector>

#include "app/model/train.hpp"

namespace nlsoft::model {

class TrainProgress {
 public:
  explicit TrainProgress(std::FILE* out);
  void operator()(const Progress& p);
  void finish();

 private:
  std::string eta(const Progress& p);

  std::FILE* out_;
  bool tty_;
  bool drawn_ = false;
  // How far each candidate is (0..1: its one-step half, then its
  // simulation half), for an ETA over the whole training.
  std::vector<double> done_;
  double last_elapsed_ = 0;
};

}  // namespace nlsoft::model
