#pragma once
// The view-importance VPL sampler as the programs run it: compiled once, in its own translation
// unit (importance_sampler.cpp), for the backends the programs list. Instantiated inside a
// program's own unit, next to its QMC sampler and pipeline, it changed how the compiler inlined
// and fused the QMC walks' arithmetic, and with it the last bits of the default sampler's images
// (Sponza_lit); out of that unit, the default images stay those of a program without it.

#include "igi/lighting/importance_vpl_sampler.hpp"
#include "igi/lighting/vpl_sampler_choice.hpp"

namespace igi::programs {

/// ImportanceVplSampler (default settings) behind a declaration: its generate is defined for
/// GltfMaterialShader, StandardBrdf and every backend of RenderBackends in importance_sampler.cpp.
class SeparateImportanceVplSampler {
 public:
  /// Policy name: ImportanceVplSampler's.
  static constexpr const char* name() noexcept { return ImportanceVplSampler::name(); }
  /// ImportanceVplSampler's: its VPLs are chosen for the frame's view.
  static constexpr bool chooses_for_view() noexcept { return ImportanceVplSampler::chooses_for_view(); }
  /// ImportanceVplSampler{}.generate(scene, tracer, shader, brdf, settings).
  template <class Tracer, class Shader, class Brdf>
  VplSets generate(const Scene& scene, const Tracer& tracer, const Shader& shader, const Brdf& brdf,
                   const VplSettings& settings) const;
};

/// The programs' --vpl-sampler: QmcVplSampler or the separately compiled importance sampler.
using ProgramVplSampler = BasicVplSamplerChoice<SeparateImportanceVplSampler>;

}  // namespace igi::programs
