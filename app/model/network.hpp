#pragma once
// The trainable network: Keras Dense and GRU layers on mini-batches, forward
// and backpropagation, in double. Parameters live in one flat vector laid out
// exactly like the weight part of a shared/model.hpp parameter block (Keras
// order, W[in][out] row-major, GRU gates z|r|h), so export is a cast to float.
//
// The GRU runs one timestep from a zero state, as the paper deploys it and as
// shared/forward.hpp evaluates it:
//   z = rec_act(x Wz + bz [+ rbz]),  r = rec_act(x Wr + br [+ rbr])
//   h~ = act(x Wh + bh + r * rbh)   (reset_after; without it the r term is 0)
//   h = (1 - z) * h~
// The recurrent kernel never meets a non-zero state, so it gets no gradient;
// it is exported as zeros.
#include <vector>

#include <Eigen/Core>

#include "app/model/random.hpp"
#include "shared/model.hpp"

namespace nlsoft::model {

struct LayerSpec {
  LayerKind kind = LayerKind::Dense;
  int units = 1;
  Activation act = Activation::Linear;
  Activation rec_act = Activation::Sigmoid;
  bool reset_after = true;
};

// A layer of `kind` as rig files and --arch ask for one: `act` where the kind
// takes a chosen activation (Dense), else the kind's own (a GRU's Keras
// defaults, reset_after), from its row in shared/layer_kind.hpp.
inline LayerSpec layer_spec(LayerKind kind, int units, Activation act) {
  const LayerKindInfo& k = layer_kind_info(kind);
  return k.free_activation ? LayerSpec{kind, units, act} : LayerSpec{kind, units, k.act, k.rec_act, true};
}

class Network {
 public:
  Network() = default;
  Network(int inputs, const std::vector<LayerSpec>& layers);

  int inputs() const { return inputs_; }
  int outputs() const;
  const std::vector<Layer>& layers() const { return layers_; }  // offsets relative to the weight block
  size_t param_count() const { return theta_.size(); }
  std::vector<double>& theta() { return theta_; }
  const std::vector<double>& theta() const { return theta_; }

  // Keras defaults: Glorot-uniform kernels, zero biases.
  void initialise(Random& rng);

  // Activations of every layer for one batch (rows = samples), kept for backward.
  struct Cache {
    std::vector<Eigen::MatrixXd> in;    // input of layer i
    std::vector<Eigen::MatrixXd> pre;   // Dense: pre-activation; GRU: gate pre-activations [z|r|h]
    std::vector<Eigen::MatrixXd> post;  // GRU: gate values [z|r|h~]; Dense: none (its activation is in[i + 1] or out)
    Eigen::MatrixXd out;
  };

  const Eigen::MatrixXd& forward(const Eigen::MatrixXd& X, Cache& c) const;
  Eigen::MatrixXd predict(const Eigen::MatrixXd& X) const;

  // grad (resized to param_count) = d loss / d theta, given dOut = d loss / d out.
  void backward(const Cache& c, const Eigen::MatrixXd& dOut, std::vector<double>& grad) const;
  // The same, adding to grad (already param_count long), and d loss / d X
  // into *dX unless null: the simulation objective carries it back to the
  // step whose prediction filled the y-history columns.
  void backward_add(const Cache& c, const Eigen::MatrixXd& dOut, std::vector<double>& grad,
                    Eigen::MatrixXd* dX) const;

 private:
  int inputs_ = 0;
  std::vector<Layer> layers_;
  std::vector<double> theta_;
};

}  // namespace nlsoft::model
