#pragma once
// LibTorch internals of the graph generator (`nuld train --arch graph`): one
// set of weights, shared by every point, computes each point's residual from
// that point's own features and messages from its nearest neighbours in the
// base set (torus_graph.h). Only the neural translation units include this
// (see fourier_mlp.h for why).
//
// Why per point: the supplement's MLP emits all N x 2 residuals from (z,
// gamma) alone, so it must relearn, for every point and every way z wraps the
// base set around the torus, what the point's neighbourhood asks of it
// (tools/experiments/neural_generator.md). Here the same
// weights see every point of every set, permuting the base set permutes the
// output, and nothing in the weights depends on N.

#include <torch/torch.h>

#include <vector>

namespace nuld {

struct GraphNetImpl : torch::nn::Module {
  // nodeFeatures and edgeFeatures: the widths of the inputs forward() takes;
  // hidden: the width of each point's state; rounds: message-passing rounds.
  // gammaFrequencies: the Fourier rows that encode gamma (a buffer, saved
  // with the weights; [0, g] when the family has no gamma).
  GraphNetImpl(torch::Tensor gammaFrequencies, std::int64_t nodeFeatures, std::int64_t edgeFeatures,
               int hidden, int rounds);

  // nodes [K, N, F], edges [K, N, k, E], neighbours [N k] (int64: the
  // neighbours of point i at [i k, (i + 1) k), shared by the K sets) or
  // [K, N k] (each set's own) -> residuals [K, N, 2], in
  // units the caller scales (the generator divides by sqrt(N)).
  //   h = relu(embed(nodes))
  //   per round: m_i = mean_j relu(self(h_i) + other(h_j) + edge(e_ij))
  //              h_i += update2(relu(update1([h_i, m_i, nodes_i])))
  //   out(h), with out starting at zero (the untrained net is its base set).
  torch::Tensor forward(const torch::Tensor &nodes, const torch::Tensor &edges,
                        const torch::Tensor &neighbours);

  struct Round {
    torch::nn::Linear self{nullptr}, other{nullptr}, edge{nullptr}, update1{nullptr},
        update2{nullptr};
  };
  torch::Tensor B;  // gammaFrequencies
  torch::nn::Linear embed{nullptr}, out{nullptr};
  std::vector<Round> rounds;
};
TORCH_MODULE(GraphNet);

}  // namespace nuld
