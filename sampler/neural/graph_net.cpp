#include "sampler/neural/graph_net.h"

#include <string>

namespace nuld {

GraphNetImpl::GraphNetImpl(torch::Tensor gammaFrequencies, std::int64_t nodeFeatures,
                           std::int64_t edgeFeatures, int hidden, int rounds_) {
  using torch::nn::Linear, torch::nn::LinearOptions;
  B = register_buffer("B", std::move(gammaFrequencies));
  embed = register_module("embed", Linear(nodeFeatures, hidden));
  for (int r = 0; r < rounds_; ++r) {
    const std::string p = "round" + std::to_string(r) + "_";
    Round round;
    round.self = register_module(p + "self", Linear(hidden, hidden));
    // Biases once per message: self's.
    round.other = register_module(p + "other", Linear(LinearOptions(hidden, hidden).bias(false)));
    round.edge =
        register_module(p + "edge", Linear(LinearOptions(edgeFeatures, hidden).bias(false)));
    round.update1 = register_module(p + "update1", Linear(2 * hidden + nodeFeatures, hidden));
    round.update2 = register_module(p + "update2", Linear(hidden, hidden));
    rounds.push_back(round);
  }
  out = register_module("out", Linear(hidden, 2));
  torch::NoGradGuard noGrad;
  out->weight.zero_();
  out->bias.zero_();
}

torch::Tensor GraphNetImpl::forward(const torch::Tensor &nodes, const torch::Tensor &edges,
                                    const torch::Tensor &neighbours) {
  const std::int64_t K = nodes.size(0), n = nodes.size(1), k = edges.size(2);
  torch::Tensor h = torch::relu(embed(nodes));
  // Per-set graphs [K, N k]: one index into the K N points of the batch.
  const bool perSet = neighbours.dim() == 2;
  const torch::Tensor flat =
      perSet ? (neighbours + torch::arange(K, torch::kInt64).mul(n).unsqueeze(1)).reshape(-1)
             : neighbours;
  for (Round &r : rounds) {
    torch::Tensor m;
    if (k > 0) {
      // The first layer of the message MLP is linear in (h_i, h_j, e_ij), so
      // it is applied per point and per edge, then gathered: no [K, N, k, 2H]
      // concatenation.
      const torch::Tensor other =
          perSet ? r.other(h).reshape({K * n, -1}).index_select(0, flat).view({K, n, k, -1})
                 : r.other(h).index_select(1, flat).view({K, n, k, -1});
      m = torch::relu(r.self(h).unsqueeze(2) + other + r.edge(edges)).mean(2);
    } else {
      m = torch::zeros_like(h);  // N = 1: no neighbours, no messages
    }
    h = h + r.update2(torch::relu(r.update1(torch::cat({h, m, nodes}, 2))));
  }
  return out(h);
}

}  // namespace nuld
