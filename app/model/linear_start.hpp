#pragma once
// A network that starts as the linear model: the output-error model (one
// linear Dense layer, least squares, then trained for its own simulation
// error; it contains ARX's) carried unchanged through the network's first n
// units of every hidden layer. Training then adds what the linear model
// leaves out, from a point that already simulates the data as well as it
// does: MATLAB's nlarx puts a linear term beside its nonlinearity for the
// same reason. The hidden units past the n that carry the map keep their
// random inputs and start with no weight out, so the network's output is the
// linear model's to the last bit of double rounding.
//
// Why: a small network started at random lands in minima far apart (a
// 233-weight network from one identification run: 3.5 to 8 % nRMSE on its
// rig's task from one seed to the next), and what those minima do between the
// data's input levels is whatever the random start left there; the
// controller's Newton step trusts it. Started from the linear model, every
// seed refines one consistent map (app/CONSOLE.md, "Which signal to train
// from", has the figures). Only a linear output holds the linear model
// unchanged: through tanh it would be a Wiener model, which measured worse
// as a start on a soft rig and on the benchmarks (app/CONSOLE.md, "Training
// the model from recorded runs").
#include <vector>

#include <Eigen/Core>

#include "app/model/network.hpp"

namespace nlsoft::model {

// Whether `layers` can hold a linear Dense layer of n outputs unchanged:
// Dense hidden layers of relu or linear units, each at least n wide, and a
// linear Dense output layer of n units.
bool holds_linear_model(const std::vector<LayerSpec>& layers, int n);

// Sets net's weights to carry `linear` (one linear Dense layer, net's
// inputs and outputs) exactly over the rows of X (normalised inputs): each
// carried unit is shifted by a constant that keeps it on for every row, with
// room to spare. The units past the first n keep the weights into them that
// net had (its random initialisation); the weights out of them are set to
// zero. Throws PipelineError, changing nothing, where net cannot hold it.
void embed_linear_model(Network& net, const Network& linear, const Eigen::MatrixXd& X);

}  // namespace nlsoft::model
