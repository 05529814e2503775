#pragma once
// The controller's per-step code (rollout, kernels, cost, Newton-Raphson,
// LDL^T) is compiled for speed inside images built for size (-Os): -O2
// between NLSOFT_HOT_BEGIN and NLSOFT_HOT_END, its fixed-count loops
// unrolled by NLSOFT_UNROLL(n). An image built size-first
// (NLSOFT_SIZE_FIRST=1: a rig file's [firmware] optimize = "size", for a
// part with little flash) keeps -Os and its loops rolled instead: less
// flash, more instructions a step (docs/rig-file.md gives both).
#define NLSOFT_PRAGMA(x) _Pragma(#x)

#if defined(NLSOFT_SIZE_FIRST) && NLSOFT_SIZE_FIRST
#define NLSOFT_HOT_BEGIN \
  NLSOFT_PRAGMA(GCC push_options) NLSOFT_PRAGMA(GCC optimize("no-tree-loop-distribute-patterns"))
#define NLSOFT_UNROLL(n)
#else
#define NLSOFT_HOT_BEGIN \
  NLSOFT_PRAGMA(GCC push_options) NLSOFT_PRAGMA(GCC optimize("O2", "no-tree-loop-distribute-patterns"))
#define NLSOFT_UNROLL(n) NLSOFT_PRAGMA(GCC unroll n)
#endif
#define NLSOFT_HOT_END NLSOFT_PRAGMA(GCC pop_options)
