#pragma once
/// \file
/// A VPL sampler chosen at run time, for programs that let the user pick one without
/// instantiating the renderer once per sampler. The choice costs one switch per frame.

#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>

#include "igi/lighting/importance_vpl_sampler.hpp"
#include "igi/lighting/qmc_vpl_sampler.hpp"
#include "igi/lighting/vpl_sampler.hpp"

namespace igi {

/// One of QmcVplSampler or `Importance` (ImportanceVplSampler, or a type that runs it, with default
/// settings), itself a VplSampler.
template <class Importance = ImportanceVplSampler>
class BasicVplSamplerChoice {
 public:
  /// Policy name.
  static constexpr const char* name() noexcept { return "choice"; }

  /// The names a VplSamplerChoice accepts, as the command line lists them.
  static constexpr const char* names() noexcept { return "qmc or importance"; }

  /// The sampler called `sampler_name` ("qmc" or "importance"); throws std::invalid_argument otherwise.
  explicit BasicVplSamplerChoice(std::string_view sampler_name) {
    if (sampler_name == QmcVplSampler::name())
      sampler_ = QmcVplSampler{};
    else if (sampler_name == Importance::name())
      sampler_ = Importance{};
    else
      throw std::invalid_argument("unknown VPL sampler '" + std::string(sampler_name) + "' (" + names() + ")");
  }

  /// Name of the chosen sampler.
  const char* chosen() const noexcept {
    return std::visit([](const auto& sampler) { return sampler.name(); }, sampler_);
  }

  /// Whether the chosen sampler chooses its VPLs for the frame's view (igi::chooses_for_view).
  bool chooses_for_view() const noexcept {
    return std::visit([](const auto& sampler) { return igi::chooses_for_view(sampler); }, sampler_);
  }

  /// The frame's VPL sets from the chosen sampler.
  template <class Tracer, class Shader, class Brdf>
    requires SurfaceShader<Shader, 1> && BrdfShader<Brdf, 1>
  VplSets generate(const Scene& scene, const Tracer& tracer, const Shader& shader, const Brdf& brdf,
                   const VplSettings& settings) const {
    return std::visit([&](const auto& sampler) { return sampler.generate(scene, tracer, shader, brdf, settings); },
                      sampler_);
  }

 private:
  std::variant<QmcVplSampler, Importance> sampler_{QmcVplSampler{}};
};

/// QmcVplSampler or ImportanceVplSampler, chosen by name.
using VplSamplerChoice = BasicVplSamplerChoice<>;

}  // namespace igi
