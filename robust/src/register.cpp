// SPDX-License-Identifier: MIT
#include "graphslam/robust/register.h"

#include <memory>

#include "graphslam/robust/kernels.h"

namespace graphslam::robust {

namespace {

template <typename K>
void add(KernelRegistry& registry, const char* name, double default_width) {
  registry.registerKernel(name, default_width,
                          [](double width) { return std::make_shared<K>(width); });
}

}  // namespace

void registerKernels(KernelRegistry& registry) {
  add<HuberKernel>(registry, "huber", kDefaultWidth);
  add<PseudoHuberKernel>(registry, "pseudo-huber", kDefaultWidth);
  add<CauchyKernel>(registry, "cauchy", kDefaultWidth);
  add<GemanMcClureKernel>(registry, "geman-mcclure", kDefaultWidth);
  add<WelschKernel>(registry, "welsch", kDefaultWidth);
  add<FairKernel>(registry, "fair", kDefaultWidth);
  add<TukeyKernel>(registry, "tukey", kDefaultWidth);
  add<SaturatedKernel>(registry, "saturated", kDefaultWidth);
  add<TruncatedLeastSquaresKernel>(registry, "tls", kDefaultWidth);
  add<DcsKernel>(registry, "dcs", kDefaultDcsPhi);
}

}  // namespace graphslam::robust
