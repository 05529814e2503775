#pragma once
// Compile-time capacities. Every array in the controller is sized from one of
// these structs, so a build states its worst case once and the linker map shows
// the RAM it costs. A firmware image picks the smallest struct that fits its
// platform; the console uses HostCapacity, which fits every preset.
//
// A capacity struct provides:
//   m, n, w      max actuators, outputs, sensor channels        (paper: m, n, w)
//   nd           max history length for u and y                 (paper: n_d = d_d)
//   N, Nc        max prediction and control horizon             (paper: N, N_c)
//   width        max layer width (a GRU counts 3 x units)
//   layers       max layer count
//   weights      max total weight + bias count of a model
//   second_order exact mode carries second derivatives through the network,
//                for the full Hessian of eq. cost2; without them it uses the
//                Gauss-Newton Hessian. Measured on the shipped models (host,
//                `simulate`): Swirl nRMSE 3.32 % with, 3.33 % without, the same
//                iteration counts, and 75 % less derivative work without, so
//                the MCU capacities leave them out and the console keeps them.
#include <cstdint>

namespace nlsoft {

template <class Cap>
struct Derived {
  static constexpr bool second_order = Cap::second_order;
  // p = n_d m + d_d n + w, the network input length (paper, "Problem Statement")
  static constexpr int p = Cap::nd * Cap::m + Cap::nd * Cap::n + Cap::w;
  // U in R^{Nc x m}, flattened: the Newton-Raphson unknowns
  static constexpr int K = Cap::Nc * Cap::m;
};

struct HostCapacity {
  static constexpr int m = 8, n = 3, w = 24, nd = 4;
  static constexpr int N = 128, Nc = 4;
  static constexpr int width = 48, layers = 8, weights = 8192;
  static constexpr bool second_order = true;
};

// Tight fits for the three platforms of the paper (PRODUCT.md, "Platforms").
struct MsdCapacity {
  static constexpr int m = 1, n = 1, w = 0, nd = 2;
  static constexpr int N = 128, Nc = 2;
  static constexpr int width = 16, layers = 4, weights = 512;
  static constexpr bool second_order = false;
};
// hasel: the paper's Dense 36 -> 5 -> 5 -> 3 (233 weights) with room to
// grow each layer to 8 units; every byte here is RAM the real board pays.
struct HaselCapacity {
  static constexpr int m = 6, n = 3, w = 18, nd = 2;
  static constexpr int N = 4, Nc = 1;
  static constexpr int width = 8, layers = 4, weights = 384;
  static constexpr bool second_order = false;
};
struct TendonCapacity {
  static constexpr int m = 2, n = 3, w = 11, nd = 2;
  static constexpr int N = 4, Nc = 3;
  static constexpr int width = 16, layers = 4, weights = 512;
  static constexpr bool second_order = false;
};

}  // namespace nlsoft
