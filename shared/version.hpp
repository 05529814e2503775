#pragma once
// The product's version, in one place: the firmware reports it in INFO, the
// console prints it for --version, and the CMake project reads these three
// lines for its own VERSION (and the package's).
namespace nlsoft {

constexpr unsigned kVersionMajor = 0;
constexpr unsigned kVersionMinor = 1;
constexpr unsigned kVersionPatch = 0;

}  // namespace nlsoft
