// The programs' importance sampler, compiled here once for their backends (see importance_sampler.hpp).
#include "common/importance_sampler.hpp"

#include "igi/backends/embree/embree_backend.hpp"
#include "igi/backends/reference/reference_backend.hpp"
#include "igi/backends/saarcor/saarcor_backend.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"

namespace igi::programs {

template <class Tracer, class Shader, class Brdf>
VplSets SeparateImportanceVplSampler::generate(const Scene& scene, const Tracer& tracer, const Shader& shader,
                                               const Brdf& brdf, const VplSettings& settings) const {
  return ImportanceVplSampler{}.generate(scene, tracer, shader, brdf, settings);
}

// Every backend type of RenderBackends (render_options.hpp), which includes igi-view's.
#define IGI_IMPORTANCE_SAMPLER_FOR(...)                                                              \
  template VplSets SeparateImportanceVplSampler::generate<__VA_ARGS__, GltfMaterialShader, StandardBrdf>( \
      const Scene&, const __VA_ARGS__&, const GltfMaterialShader&, const StandardBrdf&, const VplSettings&) const;
IGI_IMPORTANCE_SAMPLER_FOR(EmbreeBackend<1>)
IGI_IMPORTANCE_SAMPLER_FOR(EmbreeBackend<4>)
IGI_IMPORTANCE_SAMPLER_FOR(EmbreeBackend<8>)
IGI_IMPORTANCE_SAMPLER_FOR(EmbreeBackend<16>)
IGI_IMPORTANCE_SAMPLER_FOR(ReferenceBackend<1>)
IGI_IMPORTANCE_SAMPLER_FOR(ReferenceBackend<4>)
IGI_IMPORTANCE_SAMPLER_FOR(ReferenceBackend<8>)
IGI_IMPORTANCE_SAMPLER_FOR(ReferenceBackend<16>)
IGI_IMPORTANCE_SAMPLER_FOR(SaarcorBackend)
#undef IGI_IMPORTANCE_SAMPLER_FOR

}  // namespace igi::programs
