#pragma once
// Training progress for humans: a redrawn one-line bar with loss and ETA on a
// terminal, a plain line every few epochs otherwise (logs, CI).
#include <cstdio>

#include "app/model/train.hpp"

namespace nlsoft::pipeline {

class TrainProgress {
 public:
  explicit TrainProgress(std::FILE* out);
  void operator()(const Progress& p);
  void finish();

 private:
  std::FILE* out_;
  bool tty_;
  bool drawn_ = false;
};

}  // namespace nlsoft::pipeline
