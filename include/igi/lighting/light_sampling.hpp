#pragma once
/// \file
/// Light sampling with densities, for next-event estimation with multiple importance sampling
/// in the reference path tracer. `LightSampler` holds the same lights as `LightSet` (emissive
/// triangles of every instance, KHR punctual point / spot / directional lights, the environment,
/// sampled by its map's distribution and combined with BRDF sampling by MIS), picks one in
/// proportion to the same power weight (mean RGB power), and for area lights samples a point
/// uniformly on the triangle and reports the solid-angle density, so a BRDF-sampled ray that
/// hits an emitter can ask `pdf` for the density light sampling would have had.
///
/// Conventions shared with the VPL path (connect() in vpl.hpp) so that both integrate the same
/// light: a spot's profile is t^2 with t = (cos - cos_outer) / (cos_inner - cos_outer); the
/// punctual `range` is ignored; a triangle emits its material's emission factor from its front
/// face (counter-clockwise side) or both faces when double-sided. Emitters with an emissive
/// texture are left out of light sampling (the texture is not integrated into a power): the
/// path tracer still finds them by BRDF sampling, where `pdf` reports 0 for them, which keeps
/// the estimate unbiased.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <numbers>
#include <vector>

#include <glm/glm.hpp>

#include "igi/lighting/lights.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

/// One light sample seen from a receiver.
struct LightSample {
  glm::vec3 wi{0.0f};        ///< Unit direction from the receiver towards the light.
  float distance = 0.0f;     ///< Distance to the sampled point; infinity for directional lights.
  glm::vec3 incident{0.0f};  ///< Area light: emitted radiance Le; punctual: intensity x profile / d^2 (irradiance at normal incidence).
  float pdf = 0.0f;          ///< Area light: solid-angle density (choice included); punctual: choice probability.
  bool delta = false;        ///< True for punctual lights (no MIS: BRDF sampling cannot hit them).
  /// True if the sample carries light (non-zero incident light and density).
  bool usable() const noexcept { return pdf > 0.0f && (incident.x > 0.0f || incident.y > 0.0f || incident.z > 0.0f); }
};

/// The lights of a scene with power-proportional choice and density evaluation.
class LightSampler {
 public:
  /// No lights.
  LightSampler() = default;

  /// The lights of `scene` in world space.
  // Throws std::invalid_argument (LightSet's checks) on a light with negative, non-finite or
  // directionless parameters.
  explicit LightSampler(const Scene& scene) {
    [[maybe_unused]] const LightSet validation(scene);  // the same checks and messages as the VPL path
    triangle_light_.resize(scene.instances.size());
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
      const Instance& instance = scene.instances[i];
      const Mesh& mesh = scene.meshes[std::size_t(instance.mesh)];
      const Material& material = scene.material_of(instance.mesh);
      if (!material.emissive() || material.emissive_texture >= 0) continue;
      triangle_light_[i].assign(mesh.triangles.size(), -1);
      for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const glm::uvec3 v = mesh.triangles[t];
        const auto world = [&](unsigned k) { return glm::vec3(instance.transform * glm::vec4(mesh.positions[k], 1.0f)); };
        Light light;
        light.kind = Kind::triangle;
        light.position = world(v.x);
        light.edge1 = world(v.y) - light.position;
        light.edge2 = world(v.z) - light.position;
        const glm::vec3 c = glm::cross(light.edge1, light.edge2);
        const float length = glm::length(c);
        light.area = 0.5f * length;
        if (!(light.area > 0.0f) || !std::isfinite(light.area)) continue;  // zero-area: emits nothing
        light.normal = c / length;
        light.radiance = material.emission;
        light.double_sided = material.double_sided;
        const float faces = light.double_sided ? 2.0f : 1.0f;
        const float weight = mean(light.radiance) * light.area * std::numbers::pi_v<float> * faces;
        triangle_light_[i][t] = add(light, weight);
      }
    }
    const Bounds bounds = scene.bounds();
    for (const PunctualLight& punctual : scene.lights) {
      Light light;
      light.radiance = punctual.color * punctual.intensity;
      light.position = punctual.position;
      float weight = 0.0f;
      switch (punctual.kind) {
        case PunctualKind::point:
          light.kind = Kind::point;
          weight = mean(light.radiance) * 4.0f * std::numbers::pi_v<float>;
          break;
        case PunctualKind::spot: {
          light.kind = Kind::spot;
          light.normal = glm::normalize(punctual.direction);
          light.cos_outer = std::cos(punctual.outer_cone);
          light.cos_inner = std::cos(std::clamp(punctual.inner_cone, 0.0f, punctual.outer_cone));
          // The profile's integral over the sphere, as SpotEmitter::power().
          const float solid_angle =
              2.0f * std::numbers::pi_v<float> * ((1.0f - light.cos_inner) + (light.cos_inner - light.cos_outer) / 3.0f);
          weight = mean(light.radiance) * solid_angle;
          break;
        }
        case PunctualKind::directional: {
          light.kind = Kind::directional;
          light.normal = glm::normalize(punctual.direction);
          // The power the scene can receive: irradiance over a disc covering its bounding sphere (as DirectionalEmitter).
          const float radius = bounds.empty() ? 0.0f : 0.5f * glm::length(bounds.extent());
          weight = mean(light.radiance) * std::numbers::pi_v<float> * radius * radius;
          break;
        }
      }
      add(light, weight);
    }
    if (scene.environment && scene.environment->emits()) {
      // Chosen by the flux it sends through the scene's bounding sphere's disc, as LightSet weighs it.
      const float radius = bounds.empty() ? 0.0f : 0.5f * glm::length(bounds.extent());
      Light light;
      light.kind = Kind::environment;
      environment_ = scene.environment;
      environment_index_ = add(light, mean(environment_->integral()) * std::numbers::pi_v<float> * radius * radius);
    }
    normalise();
  }

  /// Number of lights that can be sampled.
  std::size_t size() const noexcept { return lights_.size(); }
  /// True if nothing can be sampled.
  bool empty() const noexcept { return lights_.empty(); }

  /// A light sample seen from `receiver`: `u_choice` picks the light, (u1, u2) the point on an area light.
  // Samples that cannot light the receiver come back with pdf 0.
  LightSample sample(const glm::vec3& receiver, float u_choice, float u1, float u2) const noexcept {
    LightSample s;
    if (lights_.empty()) return s;
    const double target = double(std::clamp(u_choice, 0.0f, 1.0f)) * total_weight_;
    auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), target);
    if (it == cumulative_.end()) --it;
    const std::size_t index = std::size_t(it - cumulative_.begin());
    const Light& light = lights_[index];
    const float choice = probability_[index];
    if (light.kind == Kind::environment) {
      const EnvironmentSample sky = environment_->sample(u1, u2);
      if (!(sky.pdf > 0.0f)) return s;
      s.wi = sky.direction;
      s.distance = std::numeric_limits<float>::infinity();
      s.incident = sky.radiance;
      s.pdf = choice * sky.pdf;
      return s;
    }
    if (light.kind == Kind::directional) {
      s.wi = -light.normal;
      s.distance = std::numeric_limits<float>::infinity();
      s.incident = light.radiance;
      s.pdf = choice;
      s.delta = true;
      return s;
    }
    glm::vec3 point = light.position;
    if (light.kind == Kind::triangle) {
      const float root = std::sqrt(u1);
      point += light.edge1 * (root * (1.0f - u2)) + light.edge2 * (root * u2);
    }
    const glm::vec3 to_light = point - receiver;
    const float d2 = glm::dot(to_light, to_light);
    if (!(d2 > 0.0f) || !std::isfinite(d2)) return s;
    s.distance = std::sqrt(d2);
    s.wi = to_light / s.distance;
    const float cos_emit = -glm::dot(light.normal, s.wi);
    switch (light.kind) {
      case Kind::triangle: {
        const float cos_light = light.double_sided ? std::abs(cos_emit) : cos_emit;
        if (!(cos_light > 0.0f)) return s;
        s.incident = light.radiance;
        s.pdf = choice * d2 / (light.area * cos_light);
        break;
      }
      case Kind::point:
        s.incident = light.radiance / d2;
        s.pdf = choice;
        s.delta = true;
        break;
      case Kind::spot: {
        const float width = std::max(light.cos_inner - light.cos_outer, 1e-6f);  // the same guard as connect()
        const float t = std::clamp((cos_emit - light.cos_outer) / width, 0.0f, 1.0f);
        s.incident = light.radiance * (t * t / d2);
        s.pdf = choice;
        s.delta = true;
        break;
      }
      case Kind::directional:
      case Kind::environment: break;  // handled above
    }
    return s;
  }

  /// True if the scene has an environment that emits.
  bool has_environment() const noexcept { return environment_index_ >= 0; }
  /// Radiance the environment sends along unit direction `-direction` (that is, seen looking
  /// along `direction`); zero without one.
  glm::vec3 environment_radiance(const glm::vec3& direction) const noexcept {
    return environment_index_ >= 0 ? environment_->radiance(direction) : glm::vec3(0.0f);
  }
  /// Solid-angle density of `sample` picking the environment's unit direction `direction` (choice included); 0 without one.
  float environment_pdf(const glm::vec3& direction) const noexcept {
    return environment_index_ >= 0 ? probability_[std::size_t(environment_index_)] * environment_->pdf(direction) : 0.0f;
  }

  /// Solid-angle density of `sample` picking `light_point` on triangle `triangle` of instance `instance` from `receiver`.
  // 0 if that triangle is not sampled (not emissive, zero area, or textured).
  float pdf(std::size_t instance, std::size_t triangle, const glm::vec3& receiver, const glm::vec3& light_point) const noexcept {
    if (instance >= triangle_light_.size() || triangle >= triangle_light_[instance].size()) return 0.0f;
    const int index = triangle_light_[instance][triangle];
    if (index < 0) return 0.0f;
    const Light& light = lights_[std::size_t(index)];
    const glm::vec3 to_light = light_point - receiver;
    const float d2 = glm::dot(to_light, to_light);
    if (!(d2 > 0.0f)) return 0.0f;
    const float cos_emit = -glm::dot(light.normal, to_light) / std::sqrt(d2);
    const float cos_light = light.double_sided ? std::abs(cos_emit) : cos_emit;
    if (!(cos_light > 0.0f)) return 0.0f;
    return probability_[std::size_t(index)] * d2 / (light.area * cos_light);
  }

 private:
  enum class Kind { triangle, point, spot, directional, environment };
  struct Light {
    Kind kind = Kind::point;
    glm::vec3 position{0.0f}, edge1{0.0f}, edge2{0.0f}, normal{0.0f, 0.0f, 1.0f}, radiance{0.0f};
    float area = 0.0f, cos_inner = 1.0f, cos_outer = 0.0f;
    bool double_sided = false;
  };
  static float mean(const glm::vec3& v) noexcept { return (v.x + v.y + v.z) / 3.0f; }
  /// Adds a light of choice weight `weight`; returns its index, or -1 if it has no power.
  int add(const Light& light, float weight) {
    if (!(weight > 0.0f) || !std::isfinite(weight)) return -1;
    lights_.push_back(light);
    total_weight_ += double(weight);
    cumulative_.push_back(total_weight_);
    weights_.push_back(weight);
    return int(lights_.size()) - 1;
  }
  /// Recomputes the choice probabilities (after the last add).
  void normalise() {
    probability_.resize(weights_.size());
    for (std::size_t i = 0; i < weights_.size(); ++i) probability_[i] = float(double(weights_[i]) / total_weight_);
  }

  std::vector<Light> lights_;
  std::vector<float> weights_, probability_;
  std::vector<double> cumulative_;
  double total_weight_ = 0.0;
  std::vector<std::vector<int>> triangle_light_;
  std::shared_ptr<const Environment> environment_;  ///< The scene's environment, if it emits.
  int environment_index_ = -1;                      ///< Its index among the lights, or -1.
};

}  // namespace igi
