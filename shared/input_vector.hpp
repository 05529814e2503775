#pragma once
// The network input vector x (length p = n_d m + d_d n + w) and the in-place
// roll of Algorithm 1 ("Input Vector Building"):
//   x = [ u(k) ... u(k-nd+1) | y(k) ... y(k-dd+1) | l(k) ]
// newest first in each queue, sensor signals last.
namespace nlsoft {

struct InputLayout {
  int m, n, w, nd, dd;
  int u_begin() const { return 0; }
  int y_begin() const { return nd * m; }
  int l_begin() const { return nd * m + dd * n; }
  int p() const { return nd * m + dd * n + w; }
};

// roll(queue, start, end, bsize): shift x[start, end) by bsize towards the end,
// dropping the oldest bsize elements and freeing x[start, start+bsize).
template <class T>
void roll(T* x, int start, int end, int bsize) {
  for (int i = end - 1; i >= start + bsize; --i) x[i] = x[i - bsize];
}

// Algorithm 1, lines 1-2: push the newest control input.
template <class T, class V>
void push_input(T* x, const InputLayout& L, const V* u) {
  roll(x, L.u_begin(), L.y_begin(), L.m);
  for (int i = 0; i < L.m; ++i) x[L.u_begin() + i] = u[i];
}

// Algorithm 1, lines 3-4: push the newest output (predicted or measured).
template <class T, class V>
void push_output(T* x, const InputLayout& L, const V* y) {
  roll(x, L.y_begin(), L.l_begin(), L.n);
  for (int j = 0; j < L.n; ++j) x[L.y_begin() + j] = y[j];
}

// Algorithm 1, line 5: the instantaneous sensor signals.
template <class T>
void set_sensors(T* x, const InputLayout& L, const float* l) {
  for (int i = 0; i < L.w; ++i) x[L.l_begin() + i] = l[i];
}

}  // namespace nlsoft
