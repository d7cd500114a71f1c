#pragma once
/// \file
/// Light sources behind one sampling interface. An emitter has a power (W, RGB) and samples
/// emission from four uniform numbers: where a light particle starts, where it goes, how much
/// flux it carries, and the VPL that stands for the emitter at that point. `LightSet` collects
/// a scene's emitters (emissive triangles as area lights, KHR punctual point / spot /
/// directional lights, the environment) plus any user-defined ones, and picks among them in proportion to power.
///
/// Conventions: a sample describes the emitter as if that one particle carried its whole power
/// (`flux` has expectation `power()`, the VPL's sum over samples is the emitter's light); a
/// sampler that shoots N particles scales both by 1 / (N x choice probability). A light's
/// scalar weight for choosing is the mean of its RGB power.

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "igi/lighting/vpl.hpp"
#include "igi/scene/environment.hpp"
#include "igi/scene/scene.hpp"
#include "igi/simd/sampling.hpp"

namespace igi {


/// One sampled light particle.
struct EmissionSample {
  Vpl vpl{};                   ///< The emitter's VPL at `origin`, carrying the emitter's whole power.
  glm::vec3 origin{0.0f};      ///< Where the particle starts.
  glm::vec3 direction{0.0f, 0.0f, 1.0f};  ///< Unit direction the particle leaves in.
  glm::vec3 flux{0.0f};        ///< Flux the particle carries (W); its expectation is the emitter's power.
  /// False where `vpl` does not stand for the emitter's direct light: the environment's, which
  /// its shared directional VPLs carry (EnvironmentLight::directional_vpls); its particles only walk.
  bool leaves_vpl = true;
};

/// What an emitter provides: `power()` (W, RGB) and `sample_emission(u1, u2, u3, u4)` with the
/// four numbers uniform in [0, 1) (u1, u2 place the particle, u3, u4 direct it).
template <class E>
concept EmitterModel = requires(const E& emitter, float u) {
  { emitter.power() } -> std::convertible_to<glm::vec3>;
  { emitter.sample_emission(u, u, u, u) } -> std::same_as<EmissionSample>;
};

/// A type-erased emitter: any EmitterModel, copied cheaply (shared, immutable).
class Emitter {
 public:
  /// Wraps `model`.
  template <EmitterModel E>
    requires(!std::same_as<std::decay_t<E>, Emitter>)
  Emitter(E model)  // NOLINT(google-explicit-constructor): any model is an emitter
      : model_(std::make_shared<const Model<E>>(std::move(model))) {}
  /// Emitted power (W, RGB).
  glm::vec3 power() const { return model_->power(); }
  /// A particle from u1..u4 in [0, 1).
  EmissionSample sample_emission(float u1, float u2, float u3, float u4) const {
    return model_->sample_emission(u1, u2, u3, u4);
  }

 private:
  struct Interface {
    virtual ~Interface() = default;
    virtual glm::vec3 power() const = 0;
    virtual EmissionSample sample_emission(float, float, float, float) const = 0;
  };
  template <class E>
  struct Model final : Interface {
    explicit Model(E e) : emitter(std::move(e)) {}
    glm::vec3 power() const override { return emitter.power(); }
    EmissionSample sample_emission(float u1, float u2, float u3, float u4) const override {
      return emitter.sample_emission(u1, u2, u3, u4);
    }
    E emitter;
  };
  std::shared_ptr<const Interface> model_;
};

/// Unit vectors `t1`, `t2` completing unit `n` to a right-handed orthonormal basis.
inline void orthonormal_basis(const glm::vec3& n, glm::vec3& t1, glm::vec3& t2) noexcept {
  // Branch on the sign of z so the division never approaches 0 (the singular point is avoided).
  const float sign = n.z >= 0.0f ? 1.0f : -1.0f;
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  t1 = glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  t2 = glm::vec3(b, sign + n.y * n.y * a, -n.y);
}

/// Cosine-distributed unit direction around unit `n` (density cos(theta) / pi).
inline glm::vec3 sample_cosine_hemisphere(const glm::vec3& n, float u1, float u2) noexcept {
  glm::vec3 t1, t2;
  orthonormal_basis(n, t1, t2);
  const float r = std::sqrt(u1), phi = 2.0f * std::numbers::pi_v<float> * u2;
  const float z = std::sqrt(std::max(0.0f, 1.0f - u1));
  return glm::normalize(t1 * (r * std::cos(phi)) + t2 * (r * std::sin(phi)) + n * z);
}

namespace light_detail {
/// Largest of the three components.
inline float largest_component(const glm::vec3& v) noexcept { return std::max(std::max(v.x, v.y), v.z); }
/// Throws std::invalid_argument unless every component of `v` is finite and >= 0.
inline void check_emission(const glm::vec3& v, const std::string& what) {
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(v[c]) || v[c] < 0.0f)
      throw std::invalid_argument(what + " must be finite and non-negative, got (" + std::to_string(v.x) + ", " +
                                  std::to_string(v.y) + ", " + std::to_string(v.z) + ")");
}
/// `v` normalised; throws std::invalid_argument naming `what` if it is zero or not finite.
inline glm::vec3 unit_direction(const glm::vec3& v, const std::string& what) {
  const float length2 = glm::dot(v, v);
  if (!(length2 > 0.0f) || !std::isfinite(length2)) throw std::invalid_argument(what + " has no direction (zero or non-finite)");
  return v / std::sqrt(length2);
}
/// The point of the triangle at `corner` with edges `edge1`, `edge2` drawn uniformly by (u1, u2).
inline glm::vec3 triangle_point(const glm::vec3& corner, const glm::vec3& edge1, const glm::vec3& edge2, float u1,
                                float u2) noexcept {
  const float root = std::sqrt(u1);
  return corner + edge1 * (root * (1.0f - u2)) + edge2 * (root * u2);
}
}  // namespace light_detail

/// A point particles are aimed at (a view point, an opening), and the radius about its line they start within.
struct AimPoint {
  glm::vec3 point{0.0f};  ///< World position.
  float spread = 0.0f;    ///< Radius about the line through `point`: about the distance to its neighbouring view points.
};

namespace light_detail {
/// `target`'s line moved onto the disc's plane (centre `centre`, normal `direction`).
inline glm::vec3 on_disc_plane(const AimPoint& target, const glm::vec3& centre, const glm::vec3& direction) noexcept {
  return target.point + direction * glm::dot(centre - target.point, direction);
}
/// The aimed particles' start about a target's line: density 2 / (pi r^2) x (1 - d^2 / r^2) at
/// distance d within its spread r, per unit area. A kernel that falls to zero at its edge, so a
/// point's density is continuous in the target's position: the float rounding by which backends'
/// hit points differ moves a particle's weight by as little, where a uniform disc's edge would
/// flip it between two weights.
inline float aim_kernel(float distance2, float spread) noexcept {
  const float spread2 = spread * spread;
  return distance2 < spread2 ? 2.0f / (std::numbers::pi_v<float> * spread2) * (1.0f - distance2 / spread2) : 0.0f;
}
/// A point drawn from aim_kernel about `centre` (in the plane spanned by `t1`, `t2`) from (u1, u2):
/// with s = d^2 / r^2 of density 2 (1 - s), s = 1 - sqrt(1 - u1).
inline glm::vec3 aim_point(const glm::vec3& centre, const glm::vec3& t1, const glm::vec3& t2, float spread, float u1,
                           float u2) noexcept {
  const float r = spread * std::sqrt(std::max(0.0f, 1.0f - std::sqrt(1.0f - u1))), phi = 2.0f * std::numbers::pi_v<float> * u2;
  return centre + t1 * (r * std::cos(phi)) + t2 * (r * std::sin(phi));
}
/// Density, per unit area of the plane through the disc, of points aimed at `targets` (each
/// moved along `direction` onto that plane: the disc's centre is `centre`, its normal
/// `direction`) by aim_kernel, each target equally likely, weighted by `weight(k)` (a direction's
/// kernel, or 1); 0 for no targets.
template <class Weight>
float aimed_density(const glm::vec3& point, const glm::vec3& centre, const glm::vec3& direction,
                    const std::vector<AimPoint>& targets, const Weight& weight) noexcept {
  if (targets.empty()) return 0.0f;
  float density = 0.0f;
  for (std::size_t k = 0; k < targets.size(); ++k) {
    const float w = weight(k);
    if (!(w > 0.0f)) continue;
    const glm::vec3 offset = point - on_disc_plane(targets[k], centre, direction);
    density += w * aim_kernel(glm::dot(offset, offset), targets[k].spread);
  }
  return density / float(targets.size());
}
/// Solid-angle density, from `position`, of directions aimed through `opening`'s disc (aim_kernel
/// on the disc across the line to it) at unit `direction`: the kernel where the direction's line
/// crosses that disc, times the distance squared over the cosine cubed (the disc's area seen as
/// solid angle from the point); 0 for directions away from it.
inline float aimed_direction_density(const glm::vec3& position, const glm::vec3& direction, const AimPoint& opening) noexcept {
  const glm::vec3 axis = opening.point - position;
  const float distance2 = glm::dot(axis, axis);
  if (!(distance2 > 0.0f)) return 0.0f;
  const float along = glm::dot(direction, axis);  // distance x cos of the angle to the axis
  if (!(along > 0.0f)) return 0.0f;
  const float cosine = along / std::sqrt(distance2);
  const glm::vec3 offset = position + direction * (distance2 / along) - opening.point;
  return aim_kernel(glm::dot(offset, offset), opening.spread) * distance2 / (cosine * cosine * cosine);
}
/// A unit direction from `position` through `opening`'s disc, drawn from aim_kernel by (u1, u2)
/// (aim_point's), whose density is aimed_direction_density.
inline glm::vec3 aimed_direction(const glm::vec3& position, const AimPoint& opening, float u1, float u2) noexcept {
  const glm::vec3 axis = opening.point - position;
  const float distance = glm::length(axis);
  glm::vec3 t1, t2;
  orthonormal_basis(axis / std::max(distance, 1e-30f), t1, t2);
  return glm::normalize(aim_point(opening.point, t1, t2, opening.spread, u1, u2) - position);
}
/// Density of the uniform point on the disc of `radius` about `centre` (in its plane): 1 / area inside, 0 outside.
inline float disc_density(const glm::vec3& point, const glm::vec3& centre, float radius) noexcept {
  const glm::vec3 offset = point - centre;
  return radius > 0.0f && glm::dot(offset, offset) <= radius * radius ? 1.0f / (std::numbers::pi_v<float> * radius * radius) : 0.0f;
}
/// A uniform point on the disc of `radius` about `centre` spanned by `t1`, `t2`, from (u1, u2).
inline glm::vec3 disc_point(const glm::vec3& centre, const glm::vec3& t1, const glm::vec3& t2, float radius, float u1,
                            float u2) noexcept {
  const float r = radius * std::sqrt(u1), phi = 2.0f * std::numbers::pi_v<float> * u2;
  return centre + t1 * (r * std::cos(phi)) + t2 * (r * std::sin(phi));
}
/// `u` in [0, 1) split at `share`: whether it fell below, and it rescaled to [0, 1) within its part.
inline std::pair<bool, float> split(float u, float share) noexcept {
  constexpr float below_one = 0x1.fffffep-1f;
  if (u < share) return {true, std::min(u / share, below_one)};
  return {false, std::min((u - share) / (1.0f - share), below_one)};
}
}  // namespace light_detail

/// A world-space triangle of uniform emitted radiance (an area light), Lambertian, emitting
/// from its front face (counter-clockwise side) or from both faces.
class TriangleEmitter {
 public:
  /// Triangle (p0, p1, p2) emitting radiance `radiance`; throws on negative or non-finite radiance.
  TriangleEmitter(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, const glm::vec3& radiance,
                  bool double_sided = false)
      : p0_(p0), e1_(p1 - p0), e2_(p2 - p0), radiance_(radiance), double_sided_(double_sided) {
    light_detail::check_emission(radiance, "TriangleEmitter radiance");
    const glm::vec3 c = glm::cross(e1_, e2_);
    const float length = glm::length(c);
    area_ = 0.5f * length;
    normal_ = length > 0.0f ? c / length : glm::vec3(0.0f, 0.0f, 1.0f);
  }
  /// The triangle with a `share` of its particles aimed through `openings` (Portals::emitter_openings
  /// of its instance: an emitter outside a window, seen through it); none aimed if there are none.
  TriangleEmitter(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, const glm::vec3& radiance,
                  bool double_sided, std::shared_ptr<const std::vector<AimPoint>> openings, float share)
      : TriangleEmitter(p0, p1, p2, radiance, double_sided) {
    if (openings && !openings->empty() && share > 0.0f && share < 1.0f) {
      openings_ = std::move(openings);
      share_ = share;
    }
  }
  /// Radiance x area x pi per emitting face.
  glm::vec3 power() const noexcept { return radiance_ * (area_ * std::numbers::pi_v<float> * (double_sided_ ? 2.0f : 1.0f)); }
  /// Uniform point (u1, u2), cosine-distributed direction (u3, u4); u3 also picks the face. With
  /// openings, u3 first picks an aimed share, whose direction goes from the point to one of the
  /// openings (picked by u3, rescaled) through its spread (aim_kernel, on the disc across the
  /// line to it, from u3's rest and u4); flux radiance x cos x area / the mixture's density.
  EmissionSample sample_emission(float u1, float u2, float u3, float u4) const noexcept {
    bool aimed = false;
    if (share_ > 0.0f) std::tie(aimed, u3) = light_detail::split(u3, share_);
    const glm::vec3 position = light_detail::triangle_point(p0_, e1_, e2_, u1, u2);
    glm::vec3 normal = normal_;
    if (double_sided_) {
      // Half of u3's range per face, rescaled to [0, 1) for the direction.
      if (u3 < 0.5f) {
        u3 *= 2.0f;
      } else {
        u3 = 2.0f * u3 - 1.0f;
        normal = -normal;
      }
    }
    EmissionSample sample;
    sample.origin = position;
    sample.direction = sample_cosine_hemisphere(normal, u3, u4);
    sample.flux = power();
    if (share_ > 0.0f) {
      if (aimed) {
        const std::size_t count = openings_->size();
        const std::size_t k = std::min(std::size_t(u3 * float(count)), count - 1);
        const float within = std::min(u3 * float(count) - float(k), 0x1.fffffep-1f);
        sample.direction = light_detail::aimed_direction(position, (*openings_)[k], u4, within);
      }
      const float cosine = glm::dot(sample.direction, normal);
      const float density = cosine > 0.0f ? (1.0f - share_) * cosine * std::numbers::inv_pi_v<float> +
                                                share_ * aimed_direction_density(position, sample.direction)
                                          : 0.0f;
      sample.flux = density > 0.0f && std::isfinite(density)
                        ? radiance_ * (cosine * area_ * (double_sided_ ? 2.0f : 1.0f) / density)
                        : glm::vec3(0.0f);
    }
    sample.vpl.position = position;
    sample.vpl.normal = normal;
    sample.vpl.kind = VplKind::surface;
    sample.vpl.intensity = power() / std::numbers::pi_v<float>;  // a Lambertian emitter of flux P has intensity P / pi along its normal
    return sample;
  }
  /// Area of the triangle.
  float area() const noexcept { return area_; }

 private:
  /// Solid-angle density of the aimed directions at `direction` from `position`, averaged over the openings.
  float aimed_direction_density(const glm::vec3& position, const glm::vec3& direction) const noexcept {
    float density = 0.0f;
    for (const AimPoint& opening : *openings_) density += light_detail::aimed_direction_density(position, direction, opening);
    return density / float(openings_->size());
  }

  glm::vec3 p0_, e1_, e2_, radiance_, normal_{0.0f, 0.0f, 1.0f};
  float area_ = 0.0f;
  bool double_sided_ = false;
  std::shared_ptr<const std::vector<AimPoint>> openings_;  ///< Where the aimed particles go through; none: none aimed.
  float share_ = 0.0f;                                     ///< Of all particles, the aimed ones (0: none).
};

/// An isotropic point light of radiant intensity `intensity` (W/sr).
class PointEmitter {
 public:
  /// Point light at `position`; throws on negative or non-finite intensity.
  PointEmitter(const glm::vec3& position, const glm::vec3& intensity) : position_(position), intensity_(intensity) {
    light_detail::check_emission(intensity, "PointEmitter intensity");
  }
  /// 4 pi x intensity.
  glm::vec3 power() const noexcept { return intensity_ * (4.0f * std::numbers::pi_v<float>); }
  /// Uniform direction on the sphere from (u3, u4).
  EmissionSample sample_emission(float, float, float u3, float u4) const noexcept {
    const float z = 1.0f - 2.0f * u3, r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 2.0f * std::numbers::pi_v<float> * u4;
    EmissionSample sample;
    sample.origin = position_;
    sample.direction = glm::normalize(glm::vec3(r * std::cos(phi), r * std::sin(phi), z));
    sample.flux = power();
    sample.vpl = {.position = position_, .normal = {0.0f, 1.0f, 0.0f}, .intensity = intensity_, .kind = VplKind::omni};
    return sample;
  }

 private:
  glm::vec3 position_, intensity_;
};

/// A spot light: intensity `intensity` (W/sr) inside the inner cone, falling off as connect()'s
/// profile t^2, t = (cos - cos_outer) / (cos_inner - cos_outer), to zero at the outer cone.
class SpotEmitter {
 public:
  /// Spot at `position` shining along `direction` with cone half-angles in radians.
  SpotEmitter(const glm::vec3& position, const glm::vec3& direction, const glm::vec3& intensity, float inner_angle,
              float outer_angle)
      : position_(position), axis_(light_detail::unit_direction(direction, "SpotEmitter direction")), intensity_(intensity) {
    light_detail::check_emission(intensity, "SpotEmitter intensity");
    if (!std::isfinite(inner_angle) || !std::isfinite(outer_angle) || outer_angle <= 0.0f || outer_angle > std::numbers::pi_v<float>)
      throw std::invalid_argument("SpotEmitter: outer cone angle must be in (0, pi], got " + std::to_string(outer_angle));
    cos_outer_ = std::cos(outer_angle);
    cos_inner_ = std::cos(std::clamp(inner_angle, 0.0f, outer_angle));
    // Integral of the profile over the sphere: full inside the inner cone, the t^2 ramp between.
    profile_solid_angle_ = 2.0f * std::numbers::pi_v<float> * ((1.0f - cos_inner_) + (cos_inner_ - cos_outer_) / 3.0f);
  }
  /// Intensity x the solid-angle integral of the profile.
  glm::vec3 power() const noexcept { return intensity_ * profile_solid_angle_; }
  /// Direction uniform in the outer cone from (u3, u4), flux weighted by the profile.
  EmissionSample sample_emission(float, float, float u3, float u4) const noexcept {
    const float cos_theta = 1.0f - u3 * (1.0f - cos_outer_);
    const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta)), phi = 2.0f * std::numbers::pi_v<float> * u4;
    glm::vec3 t1, t2;
    orthonormal_basis(axis_, t1, t2);
    const float width = std::max(cos_inner_ - cos_outer_, 1e-6f);  // the same guard as connect()
    const float t = std::clamp((cos_theta - cos_outer_) / width, 0.0f, 1.0f);
    const float cone_solid_angle = 2.0f * std::numbers::pi_v<float> * (1.0f - cos_outer_);
    EmissionSample sample;
    sample.origin = position_;
    sample.direction = glm::normalize(t1 * (sin_theta * std::cos(phi)) + t2 * (sin_theta * std::sin(phi)) + axis_ * cos_theta);
    // Uniform density 1 / cone; emitted flux density intensity x profile: weight profile x cone / integral.
    sample.flux = profile_solid_angle_ > 0.0f ? power() * (t * t * cone_solid_angle / profile_solid_angle_) : glm::vec3(0.0f);
    sample.vpl = {.position = position_,
                  .normal = axis_,
                  .intensity = intensity_,
                  .kind = VplKind::spot,
                  .cos_inner = cos_inner_,
                  .cos_outer = cos_outer_};
    return sample;
  }

 private:
  glm::vec3 position_, axis_, intensity_;
  float cos_inner_ = 1.0f, cos_outer_ = 0.0f, profile_solid_angle_ = 0.0f;
};


/// Openings through which light from infinitely far away (the sun, the sky) reaches what the
/// camera sees, found each frame by rays from the view's points that leave the scene
/// (find_portals in portals.hpp). A `share` of the particles of directional lights and of the
/// environment is aimed along those rays, the rest spread as without portals: the density of
/// the mixture weighs every particle, so the light's estimate keeps its expectation while far
/// more particles pass the window of a room the camera is in.
struct Portals {
  /// For each punctual light of the scene, by its index (empty for all but directional
  /// lights): view points from which a ray towards the light left the scene.
  std::vector<std::vector<AimPoint>> sunlit{};
  std::vector<AimPoint> sky_points{};     ///< View points from which a ray towards the environment left the scene.
  std::vector<glm::vec3> sky_directions{}; ///< Those rays' unit directions, towards the sky.
  /// Where rays from the view's points that left the scene pass their openings (a window's frame
  /// beside them; a ray's start where open sky is all around it), spread about as far as the
  /// next such point: the sky's rays, one for each of sky_points, or without an environment rays
  /// about the points' normals. The sky's particles aimed there by its own directions enter
  /// through the whole opening.
  std::vector<AimPoint> openings{};
  /// Those of `openings` that have a frame (the rest are the start of a ray in the open, where the
  /// sunlit points already aim), spread among themselves: a directional light's particles are
  /// also aimed through these, so its light reaches what no view point shows lit (a window's
  /// sill, the floor behind the furniture) and bounces into the room.
  std::vector<AimPoint> framed_openings{};
  /// Those of framed_openings that the view's own points found (not the surfaces they see), if
  /// the view is enclosed (find_portals: few of its sky rays leave): where the view's room opens
  /// to the outside. Heavy light particles that bounce outside are aimed back in through them
  /// (BounceOpenings).
  std::vector<AimPoint> view_openings{};
  /// The unit directions, towards the sky, of the rays that passed view_openings (parallel to it).
  std::vector<glm::vec3> view_opening_directions{};
  /// For each instance of the scene, by its index (empty for most): the framed openings through
  /// which rays from the view's points reach its emission, as a sky panel or an emissive dome
  /// outside a window, if they reach it through openings at least half the time (else it lights
  /// the view from where it is); its triangles' particles are aimed through them. Looked for
  /// with the other portals, in scenes with a directional light or an environment.
  std::vector<std::vector<AimPoint>> emitter_openings{};
  float share = 0.0f;                     ///< Fraction of the particles aimed, in [0, 1).
  /// True if some particle would be aimed.
  bool any() const noexcept {
    if (!(share > 0.0f)) return false;
    if (!sky_points.empty() || !framed_openings.empty()) return true;
    for (const auto& points : emitter_openings)
      if (!points.empty()) return true;
    for (const auto& points : sunlit)
      if (!points.empty()) return true;
    return false;
  }
};

/// Of a diffuse bounce aimed back in through the view's openings (BounceOpenings), the share of
/// directions aimed: a half, so the weight of the other directions at most doubles (they light
/// the outside, which the view rarely sees), while a bounce into the room is drawn about as
/// often as a particle aimed there from the light.
inline constexpr float bounce_aim_share = 0.5f;
/// A bounce is not aimed through an opening whose escape ray (the view's ray that found it,
/// towards the sky) lies within 60 degrees of the line from the bounce to it: from there a
/// particle through the opening would leave the way that ray left rather than enter (the forest
/// floor below a gap in the canopy, the room's floor below its window), while the ground just
/// outside a window, which sees the window steeply above it, is aimed.
inline constexpr float bounce_escape_cosine = 0.5f;

/// The view's openings as a light particle's diffuse bounce sees them from outside. A share of
/// the bounce's directions is aimed back in through those in front of it (bounce_escape_cosine
/// says which), and every direction is weighed by the mixture's density, so the estimate keeps
/// its expectation. Without it, the light that the ground outside reflects into a room reached
/// it only when a cosine-distributed bounce happened to pass the window: rarely, and heavily
/// when a particle that missed every aimed target (so carrying the light of a large part of the
/// emitting disc) did so; one such walk, dissected in the window room, left six VPLs a hundred
/// times brighter than the room's others and made the frame twice as bright as it should be.
/// The sampler aims only the first bounce of such heavy particles (LightSet::heavy_flux): a
/// light particle landed where light was aimed, in the room or on what the view sees, and a
/// heavy one that has bounced once more may be inside, where aiming out would waste its bounces.
class BounceOpenings {
 public:
  /// No openings: every bounce cosine-distributed.
  BounceOpenings() = default;
  /// Bounces aimed through `openings` (Portals::view_openings), whose escape rays' directions
  /// `outward` (Portals::view_opening_directions, parallel) give; throws std::invalid_argument
  /// if their sizes differ.
  BounceOpenings(std::vector<AimPoint> openings, std::vector<glm::vec3> outward)
      : openings_(std::move(openings)), outward_(std::move(outward)) {
    if (openings_.size() != outward_.size())
      throw std::invalid_argument("BounceOpenings: " + std::to_string(openings_.size()) + " openings but " +
                                  std::to_string(outward_.size()) + " outward directions");
  }
  /// True if no bounce is aimed.
  bool empty() const noexcept { return openings_.empty(); }

  /// A diffuse bounce's direction, and the weight it carries on top of the cosine lobe's.
  struct Bounce {
    glm::vec3 direction{0.0f};  ///< Unit direction, above the geometric surface.
    float weight = 1.0f;        ///< The cosine lobe's density over the mixture's: 1 where nothing is aimed; 0 for a wasted sample.
  };
  /// The continuation from `position` on a surface with geometric normal `geometric` (on the
  /// side the particle came from) and shading normal `normal` (its cosine lobe's axis, on the
  /// same side): cosine-distributed from (u1, u2), a direction that falls under the surface
  /// mirrored back above it (a bumped normal's); where `aim` is set and openings are in front,
  /// u1 first picks the aimed share, then the opening and, with u2, the point of its disc to pass.
  Bounce sample(const glm::vec3& position, const glm::vec3& normal, const glm::vec3& geometric, float u1, float u2,
                bool aim) const noexcept {
    std::size_t seen = 0;
    if (aim)
      for (std::size_t k = 0; k < openings_.size(); ++k) seen += aims_through(k, position, geometric);
    if (seen == 0) return {cosine_direction(normal, geometric, u1, u2), 1.0f};
    const auto [aimed, u] = light_detail::split(u1, bounce_aim_share);
    glm::vec3 direction;
    if (aimed) {
      const std::size_t pick = std::min(std::size_t(u * float(seen)), seen - 1);
      const float within = std::min(u * float(seen) - float(pick), 0x1.fffffep-1f);
      std::size_t k = 0;
      for (std::size_t found = 0;; ++k)
        if (aims_through(k, position, geometric) && found++ == pick) break;
      direction = light_detail::aimed_direction(position, openings_[k], u2, within);
      if (!(glm::dot(direction, geometric) > 0.0f)) return {direction, 0.0f};
    } else {
      direction = cosine_direction(normal, geometric, u, u2);
    }
    // The cosine lobe's density, folded as cosine_direction folds it.
    const glm::vec3 folded = direction - 2.0f * glm::dot(direction, geometric) * geometric;
    const float cosine_density =
        (std::max(0.0f, glm::dot(normal, direction)) + std::max(0.0f, glm::dot(normal, folded))) * std::numbers::inv_pi_v<float>;
    float aimed_density = 0.0f;
    for (std::size_t k = 0; k < openings_.size(); ++k)
      if (aims_through(k, position, geometric)) aimed_density += light_detail::aimed_direction_density(position, direction, openings_[k]);
    const float mixture = (1.0f - bounce_aim_share) * cosine_density + bounce_aim_share * aimed_density / float(seen);
    const float weight = cosine_density / mixture;
    return {direction, mixture > 0.0f && std::isfinite(weight) ? weight : 0.0f};
  }

 private:
  /// Whether a bounce at `position` (geometric normal `geometric`) aims through opening `k`: in
  /// front of its surface, and not along the opening's escape ray (bounce_escape_cosine).
  bool aims_through(std::size_t k, const glm::vec3& position, const glm::vec3& geometric) const noexcept {
    const glm::vec3 to_opening = openings_[k].point - position;
    return glm::dot(to_opening, geometric) > 0.0f &&
           glm::dot(to_opening, outward_[k]) < bounce_escape_cosine * glm::length(to_opening);
  }
  /// A cosine-distributed direction about `normal` from (u1, u2), mirrored above the geometric surface if under it.
  static glm::vec3 cosine_direction(const glm::vec3& normal, const glm::vec3& geometric, float u1, float u2) noexcept {
    const glm::vec3 direction = sample_cosine_hemisphere(normal, u1, u2);
    const float below = glm::dot(direction, geometric);
    return below <= 0.0f ? glm::normalize(direction - 2.0f * below * geometric) : direction;
  }

  std::vector<AimPoint> openings_;
  std::vector<glm::vec3> outward_;
};

/// A particle of a light outside the view's openings (the sun, the sky, an emitter beyond a
/// window) is heavy when it carries at least this many times the flux of the light's median
/// particle (the aimed ones, 70% of them at the default share, set the median): it landed
/// where little was aimed, on the ground far outside, and its bounce into the room is the
/// rare heavy event BounceOpenings removes. 4: in the window and blinds rooms, with and without
/// sky, the particles of the sun, the sky and the sky panel fall in two groups with a gap
/// between about 2.5x and 9x the median: the aimed, about the median, and the rest, 9-650x it
/// (33-45% of all are heavy at 4x).
inline constexpr float heavy_particle_factor = 4.0f;
/// Particles drawn (no ray traced) to find a light's median flux: 64 place the median of the
/// 70% aimed among the rest to a few percent of the threshold's scale.
inline constexpr int median_flux_particles = 64;

/// Half-angle of the cone about an escape direction within which aimed sky particles travel:
/// 0.1 rad (6 degrees), about the angle between neighbouring escape rays of one view point, and
/// half the angle a 2 m window subtends from 10 m, so most aimed particles still pass.
inline constexpr float portal_cone_angle = 0.1f;


/// A directional light of irradiance `irradiance` (W/m^2 on a perpendicular surface). Particles
/// start on a disc perpendicular to the light that covers the scene's bounding sphere, placed
/// upstream of it, so every point of the scene is reachable and the disc's power is the light
/// the scene can receive.
class DirectionalEmitter {
 public:
  /// Light travelling along `direction`, covering `scene_bounds`.
  DirectionalEmitter(const glm::vec3& direction, const glm::vec3& irradiance, const Bounds& scene_bounds)
      : direction_(light_detail::unit_direction(direction, "DirectionalEmitter direction")), irradiance_(irradiance) {
    light_detail::check_emission(irradiance, "DirectionalEmitter irradiance");
    if (!scene_bounds.empty()) {
      radius_ = 0.5f * glm::length(scene_bounds.extent());
      center_ = scene_bounds.center() - direction_ * radius_;
    }
    orthonormal_basis(direction_, t1_, t2_);
  }
  /// The light with a `share` of its particles aimed at `targets` (view points it reaches from
  /// outside, Portals::sunlit) and through `openings` (Portals::framed_openings), half each when both
  /// are given: they start within a point's spread of its line; none aimed if both are empty.
  DirectionalEmitter(const glm::vec3& direction, const glm::vec3& irradiance, const Bounds& scene_bounds,
                     std::vector<AimPoint> targets, float share, std::vector<AimPoint> openings = {})
      : DirectionalEmitter(direction, irradiance, scene_bounds) {
    if ((!targets.empty() || !openings.empty()) && share > 0.0f && share < 1.0f) {
      targets_ = std::move(targets);
      openings_ = std::move(openings);
      share_ = share;
    }
  }
  /// Irradiance x disc area.
  glm::vec3 power() const noexcept { return irradiance_ * (std::numbers::pi_v<float> * radius_ * radius_); }
  /// A point on the disc from (u1, u2): uniform over it, or with an aimed share (picked by u3;
  /// the target or the opening by u4) about a point's line (aim_kernel); flux irradiance / density.
  EmissionSample sample_emission(float u1, float u2, float u3, float u4) const noexcept {
    EmissionSample sample;
    sample.origin = light_detail::disc_point(center_, t1_, t2_, radius_, u1, u2);
    sample.flux = power();
    if (share_ > 0.0f) {
      if (light_detail::split(u3, share_).first) {
        const auto [at_target, v] = light_detail::split(u4, targets_share());
        const std::vector<AimPoint>& points = at_target ? targets_ : openings_;
        const AimPoint& target = points[std::min(std::size_t(v * float(points.size())), points.size() - 1)];
        sample.origin = light_detail::aim_point(light_detail::on_disc_plane(target, center_, direction_), t1_, t2_,
                                                target.spread, u1, u2);
      }
      const auto aimed_at = [&](const std::vector<AimPoint>& points) {
        return light_detail::aimed_density(sample.origin, center_, direction_, points, [](std::size_t) { return 1.0f; });
      };
      const float to_targets = targets_share();
      const float density = (1.0f - share_) * light_detail::disc_density(sample.origin, center_, radius_) +
                            share_ * (to_targets * aimed_at(targets_) + (1.0f - to_targets) * aimed_at(openings_));
      sample.flux = density > 0.0f ? irradiance_ / density : glm::vec3(0.0f);
    }
    sample.direction = direction_;
    sample.vpl = {.position = sample.origin, .normal = direction_, .intensity = irradiance_, .kind = VplKind::directional};
    return sample;
  }
  /// Radius of the emitting disc.
  float radius() const noexcept { return radius_; }

 private:
  glm::vec3 direction_, irradiance_, center_{0.0f}, t1_{1, 0, 0}, t2_{0, 1, 0};
  float radius_ = 0.0f;
  std::vector<AimPoint> targets_;   ///< Sunlit view points the aimed particles go to.
  std::vector<AimPoint> openings_;  ///< Openings they pass through.
  float share_ = 0.0f;              ///< Of all particles, the aimed ones (0: none).
  /// Of the aimed particles, those aimed at the targets: half when there are openings too, an
  /// even split (the targets are what the view shows lit, the openings all the light can reach).
  float targets_share() const noexcept { return openings_.empty() ? 1.0f : targets_.empty() ? 0.0f : 0.5f; }
};

/// The environment (a sky) as a light. Its direct light reaches the view through a few
/// directional VPLs shared by every interleaving set (directional_vpls), drawn in proportion to
/// the environment's light, so each pixel sees the same sky and no per-pixel noise is left for
/// the filter. Its light particles, which carry the sky's light into the scene for the bounce
/// light, start on a disc perpendicular to a sampled direction that covers the scene's
/// bounding sphere, upstream of it, as a directional light's do.
class EnvironmentLight {
 public:
  /// `environment` (shared) around a scene of world `scene_bounds`.
  EnvironmentLight(std::shared_ptr<const Environment> environment, const Bounds& scene_bounds)
      : environment_(std::move(environment)) {
    if (!environment_) throw std::invalid_argument("EnvironmentLight: no environment");
    if (!scene_bounds.empty()) {
      radius_ = 0.5f * glm::length(scene_bounds.extent());
      center_ = scene_bounds.center();
    }
  }
  /// The light with a `share` of its particles aimed along the escape rays (`points`,
  /// unit `directions` towards the sky; Portals::sky_points, sky_directions) and through their
  /// `openings` (Portals::openings; the points themselves if empty or of another count):
  /// see sample_emission. None aimed if there are no points.
  EnvironmentLight(std::shared_ptr<const Environment> environment, const Bounds& scene_bounds, std::vector<AimPoint> points,
                   std::vector<glm::vec3> directions, float share, std::vector<AimPoint> openings = {})
      : EnvironmentLight(std::move(environment), scene_bounds) {
    if (!points.empty() && points.size() == directions.size() && share > 0.0f && share < 1.0f) {
      openings_ = openings.size() == points.size() ? std::move(openings) : points;
      aimed_points_ = std::move(points);
      aimed_directions_ = std::move(directions);
      share_ = share;
    }
  }
  /// The environment.
  const Environment& environment() const noexcept { return *environment_; }
  /// The flux that crosses the disc from every direction: pi r^2 x the radiance's integral over the sphere.
  glm::vec3 power() const noexcept { return environment_->integral() * (std::numbers::pi_v<float> * radius_ * radius_); }
  /// A particle: direction from (u3, u4) in proportion to the light, a uniform point on that
  /// direction's disc from (u1, u2); flux L / density (density per unit solid angle and disc
  /// area, pdf / pi r^2 without aiming), whose expectation is power(). With escape rays, u3
  /// first picks an aimed share, then which of the two aimed parts, then (rescaled) the escape
  /// ray k. Along the ray: u3 (rescaled) with u4 a direction in its cone (cone_kernel), and
  /// (u1, u2) a start about the line through ray k's view point in that direction. Through the
  /// opening: the light's own direction from u3 (rescaled) and u4, and (u1, u2) a start about
  /// the line through ray k's opening in that direction (aim_kernel either way).
  EmissionSample sample_emission(float u1, float u2, float u3, float u4) const noexcept {
    EmissionSample sample;
    sample.leaves_vpl = false;
    sample.flux = glm::vec3(0.0f);
    const auto [aimed, u] = aimed_points_.empty() ? std::pair<bool, float>{false, u3} : light_detail::split(u3, share_);
    glm::vec3 to_sky;
    std::size_t k = 0;
    bool through_opening = false;
    if (aimed) {
      const auto [along_ray, v] = light_detail::split(u, along_ray_share);
      through_opening = !along_ray;
      const std::size_t count = aimed_points_.size();
      k = std::min(std::size_t(v * float(count)), count - 1);
      const float within = std::min(v * float(count) - float(k), 0x1.fffffep-1f);
      if (along_ray) {
        // In the cone by cone_kernel: t = (1 - cos theta) / (1 - cos angle) of density 2 (1 - t).
        const float t = 1.0f - std::sqrt(1.0f - within);
        const float cos_theta = 1.0f - t * (1.0f - cos_cone_), sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
        const float phi = 2.0f * std::numbers::pi_v<float> * u4;
        glm::vec3 a1, a2;
        orthonormal_basis(aimed_directions_[k], a1, a2);
        to_sky = glm::normalize(a1 * (sin_theta * std::cos(phi)) + a2 * (sin_theta * std::sin(phi)) + aimed_directions_[k] * cos_theta);
      } else {
        const EnvironmentSample sky = environment_->sample(within, u4);
        if (!(sky.pdf > 0.0f)) return sample;
        to_sky = sky.direction;
      }
    } else {
      const EnvironmentSample sky = environment_->sample(u, u4);
      if (!(sky.pdf > 0.0f)) return sample;
      to_sky = sky.direction;
    }
    glm::vec3 t1, t2;
    orthonormal_basis(to_sky, t1, t2);
    const glm::vec3 centre = center_ + to_sky * radius_;
    if (aimed) {
      const AimPoint& target = through_opening ? openings_[k] : aimed_points_[k];
      sample.origin = light_detail::aim_point(light_detail::on_disc_plane(target, centre, to_sky), t1, t2, target.spread, u1, u2);
    } else {
      sample.origin = light_detail::disc_point(centre, t1, t2, radius_, u1, u2);
    }
    sample.direction = -to_sky;
    const float density = emission_density(sample.origin, to_sky, centre);
    if (density > 0.0f) sample.flux = environment_->radiance(to_sky) / density;
    sample.vpl = {.position = sample.origin, .normal = sample.direction, .intensity = glm::vec3(0.0f), .kind = VplKind::directional};
    return sample;
  }
  /// `count` directional VPLs that together estimate the environment's direct light: directions
  /// from the first `count` points of the Halton sequence scrambled by `scramble` (bases 2 and 3,
  /// well spread over the map's distribution), each of irradiance L / (count x pdf), so their sum
  /// over a receiver's visible directions is an unbiased estimate of its irradiance.
  std::vector<Vpl> directional_vpls(int count, std::uint32_t scramble) const {
    std::vector<Vpl> vpls;
    if (count <= 0 || !environment_->emits()) return vpls;
    const Halton halton(scramble);
    vpls.reserve(std::size_t(count));
    for (int k = 0; k < count; ++k) {
      const EnvironmentSample sky = environment_->sample(halton.sample(0, std::uint64_t(k)), halton.sample(1, std::uint64_t(k)));
      if (!(sky.pdf > 0.0f) || !(light_detail::largest_component(sky.radiance) > 0.0f)) continue;
      vpls.push_back({.position = center_ + sky.direction * radius_,
                      .normal = -sky.direction,
                      .intensity = sky.radiance / (float(count) * sky.pdf),
                      .kind = VplKind::directional});
    }
    return vpls;
  }
  /// Radius of the emitting disc (the scene's bounding sphere).
  float radius() const noexcept { return radius_; }

 private:
  /// Density of a particle travelling from unit direction `to_sky` that starts at `origin` on
  /// that direction's disc (centred at `centre`), per unit solid angle and disc area: the
  /// mixture of the map's directions over the whole disc and the aimed share.
  float emission_density(const glm::vec3& origin, const glm::vec3& to_sky, const glm::vec3& centre) const noexcept {
    const float light_pdf = environment_->pdf(to_sky);
    const float spread_out = light_pdf * light_detail::disc_density(origin, centre, radius_);
    if (aimed_points_.empty()) return spread_out;
    const float along_rays = light_detail::aimed_density(
        origin, centre, to_sky, aimed_points_, [&](std::size_t k) { return cone_kernel(glm::dot(to_sky, aimed_directions_[k])); });
    const float through_openings =
        light_pdf > 0.0f ? light_pdf * light_detail::aimed_density(origin, centre, to_sky, openings_, [](std::size_t) { return 1.0f; })
                         : 0.0f;
    return (1.0f - share_) * spread_out + share_ * (along_ray_share * along_rays + (1.0f - along_ray_share) * through_openings);
  }
  /// Solid-angle density of an aimed direction at cosine `cosine` from its escape ray's: 2 (1 - t)
  /// over the cone's solid angle, t = (1 - cosine) / (1 - cos angle), falling to zero at the
  /// cone's edge (continuous, as aim_kernel is, so backends' rounding moves weights little).
  float cone_kernel(float cosine) const noexcept {
    if (!(cosine > cos_cone_)) return 0.0f;
    const float t = (1.0f - cosine) / (1.0f - cos_cone_);
    return 2.0f * (1.0f - t) / (2.0f * std::numbers::pi_v<float> * (1.0f - cos_cone_));
  }

  std::shared_ptr<const Environment> environment_;
  glm::vec3 center_{0.0f};
  float radius_ = 0.0f;
  std::vector<AimPoint> aimed_points_;       ///< Where the escape rays the aimed particles follow start; empty: none aimed.
  std::vector<glm::vec3> aimed_directions_;  ///< Their directions, towards the sky.
  float share_ = 0.0f;
  float cos_cone_ = std::cos(portal_cone_angle);
  std::vector<AimPoint> openings_;           ///< Where those rays pass their openings (the points themselves where unknown).
  /// Of the aimed particles, the share that follows the escape rays' cones: the directions by
  /// which the view's points are known to see the sky, so nearly all of them pass the opening.
  /// The rest take the sky's own directions through the openings where the escape rays left,
  /// so that light coming in from any direction a window admits, onto any point of the room,
  /// has an aimed density (with cones alone, a window's light from directions between the cones
  /// came only from the unaimed share, a few heavy particles whose luck made whole frames too
  /// bright; docs/sky.md, part 2b). The openings carry most of a room's sky light (85-90% of
  /// it, measured in the window, blinds and two-window rooms), so they take three quarters: in
  /// all three rooms the in-room flux's variance per particle was 1.5x lower than with halves.
  static constexpr float along_ray_share = 0.25f;
};

/// The VPL's emitted flux as the pipeline will see it: pi x intensity for surface VPLs, 4 pi x
/// intensity for omni, the profile integral for spots; for directional VPLs (which have no
/// finite flux) `directional_area` x irradiance.
inline glm::vec3 vpl_flux(const Vpl& vpl, float directional_area) noexcept {
  switch (vpl.kind) {
    case VplKind::surface: return vpl.intensity * std::numbers::pi_v<float>;
    case VplKind::omni: return vpl.intensity * (4.0f * std::numbers::pi_v<float>);
    case VplKind::spot:
      return vpl.intensity * (2.0f * std::numbers::pi_v<float> * ((1.0f - vpl.cos_inner) + (vpl.cos_inner - vpl.cos_outer) / 3.0f));
    case VplKind::directional: return vpl.intensity * directional_area;
  }
  return glm::vec3(0.0f);
}

/// All emitters of a scene, chosen in proportion to power.
class LightSet {
 public:
  /// No lights.
  LightSet() = default;
  /// The emissive triangles of every instance (world space; radiance = the material's emission
  /// factor, an emissive texture is not integrated) and the punctual lights of `scene`. Throws
  /// std::invalid_argument on a light with negative, non-finite or directionless parameters.
  explicit LightSet(const Scene& scene) : LightSet(scene, scene.bounds()) {}
  /// LightSet(scene) with the scene's world `bounds` given (SceneBounds), sparing a walk over
  /// every vertex; they place the lights at infinity. With `portals`, the particles of
  /// directional lights and of the environment are partly aimed through them.
  LightSet(const Scene& scene, const Bounds& bounds, const Portals* portals = nullptr) {
    const bool aimed = portals && portals->any();
    if (aimed) bounce_openings_ = BounceOpenings(portals->view_openings, portals->view_opening_directions);
    for (std::size_t instance_index = 0; instance_index < scene.instances.size(); ++instance_index) {
      const Instance& instance = scene.instances[instance_index];
      if (instance.mesh < 0 || std::size_t(instance.mesh) >= scene.meshes.size())
        throw std::invalid_argument("LightSet: instance '" + instance.name + "' refers to mesh " +
                                    std::to_string(instance.mesh) + " which the scene lacks");
      const Mesh& mesh = scene.meshes[std::size_t(instance.mesh)];
      const Material& material = scene.material_of(instance.mesh);
      if (!material.emissive()) continue;
      light_detail::check_emission(material.emission, "LightSet: emission of material '" + material.name + "'");
      // Shared by the instance's triangles (a dome may have thousands).
      std::shared_ptr<const std::vector<AimPoint>> openings;
      if (portals && portals->share > 0.0f && instance_index < portals->emitter_openings.size() &&
          !portals->emitter_openings[instance_index].empty())
        openings = std::make_shared<const std::vector<AimPoint>>(portals->emitter_openings[instance_index]);
      std::vector<TriangleEmitter> triangles;
      for (const glm::uvec3& t : mesh.triangles) {
        if (t.x >= mesh.positions.size() || t.y >= mesh.positions.size() || t.z >= mesh.positions.size())
          throw std::invalid_argument("LightSet: mesh '" + mesh.name + "' indexes a vertex it lacks");
        const auto world = [&](unsigned i) { return glm::vec3(instance.transform * glm::vec4(mesh.positions[i], 1.0f)); };
        TriangleEmitter emitter(world(t.x), world(t.y), world(t.z), material.emission, material.double_sided, openings,
                                portals ? portals->share : 0.0f);
        if (emitter.area() > 0.0f) triangles.push_back(std::move(emitter));
      }
      // An instance outside the view's openings: its triangles' heavy fluxes from its largest
      // one's median, in proportion to their areas (a particle's flux is), so a dome of
      // thousands of triangles draws its 64 particles once.
      float heavy_per_area = std::numeric_limits<float>::infinity();
      if (openings && !bounce_openings_.empty() && !triangles.empty()) {
        const auto largest = std::max_element(triangles.begin(), triangles.end(), [](const TriangleEmitter& a, const TriangleEmitter& b) {
          return a.area() < b.area();
        });
        heavy_per_area = heavy_particle_factor * median_flux(*largest) / largest->area();
      }
      for (TriangleEmitter& triangle : triangles) {
        const float heavy = heavy_per_area * triangle.area();
        add_with_heavy(std::move(triangle), heavy);
      }
    }
    for (std::size_t index = 0; index < scene.lights.size(); ++index) {
      const PunctualLight& light = scene.lights[index];
      const std::string what = "LightSet: light '" + light.name + "'";
      if (!std::isfinite(light.intensity) || light.intensity < 0.0f)
        throw std::invalid_argument(what + " has intensity " + std::to_string(light.intensity));
      const glm::vec3 radiant = light.color * light.intensity;
      try {
        switch (light.kind) {
          case PunctualKind::point: add(PointEmitter(light.position, radiant)); break;
          case PunctualKind::spot:
            add(SpotEmitter(light.position, light.direction, radiant, light.inner_cone, light.outer_cone));
            break;
          case PunctualKind::directional:
            if (aimed && index < portals->sunlit.size())
              add(DirectionalEmitter(light.direction, radiant, bounds, portals->sunlit[index], portals->share,
                                     portals->framed_openings),
                  true);
            else
              add(DirectionalEmitter(light.direction, radiant, bounds));
            break;
        }
      } catch (const std::invalid_argument& error) {
        throw std::invalid_argument(what + ": " + error.what());
      }
    }
    if (scene.environment && scene.environment->emits()) {
      if (aimed && !portals->sky_points.empty())
        add(EnvironmentLight(scene.environment, bounds, portals->sky_points, portals->sky_directions, portals->share,
                             portals->openings),
            true);
      else
        add(EnvironmentLight(scene.environment, bounds));
    }
  }

  /// Adds an emitter (user-defined or built-in); emitters without power are ignored. If it is
  /// `outside` the view's openings (a light they were found for), its heavy particles' bounces
  /// are aimed back in through them (heavy_flux).
  void add(Emitter emitter, bool outside = false) {
    const float heavy = outside && !bounce_openings_.empty() ? heavy_particle_factor * median_flux(emitter)
                                                             : std::numeric_limits<float>::infinity();
    add_with_heavy(std::move(emitter), heavy);
  }
  /// Where the particles' diffuse bounces outside the view's openings are aimed back in through them.
  const BounceOpenings& bounce_openings() const noexcept { return bounce_openings_; }
  /// The flux (largest component, as sample_emission gives it) from which a particle of emitter
  /// `i` is heavy and its bounces are aimed back in through the view's openings: infinite for
  /// an emitter inside or where there are no openings.
  float heavy_flux(std::size_t i) const noexcept { return heavy_[i]; }
  /// Number of emitters.
  std::size_t size() const noexcept { return emitters_.size(); }
  /// True if nothing emits.
  bool empty() const noexcept { return emitters_.empty(); }
  /// Emitter `i`.
  const Emitter& emitter(std::size_t i) const noexcept { return emitters_[i]; }
  /// Sum of the emitters' scalar weights (mean RGB power), W.
  double total_weight() const noexcept { return total_weight_; }
  /// Sum of the emitters' RGB power, W.
  glm::vec3 total_power() const {
    glm::dvec3 sum(0.0);
    for (const Emitter& e : emitters_) sum += glm::dvec3(e.power());
    return glm::vec3(sum);
  }

  /// An emitter picked by `u` in [0, 1) with probability weight / total weight.
  struct Choice {
    std::size_t index = 0;    ///< The emitter.
    float probability = 0.0f; ///< Its probability.
    float u = 0.0f;           ///< `u` rescaled to [0, 1) within the emitter's interval (reusable).
  };
  /// Picks an emitter by inverting the power CDF; requires a non-empty set.
  Choice choose(float u) const {
    if (empty()) throw std::logic_error("LightSet::choose: there are no emitters");
    const double target = double(std::clamp(u, 0.0f, 1.0f)) * total_weight_;
    auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), target);
    if (it == cumulative_.end()) --it;
    const std::size_t index = std::size_t(it - cumulative_.begin());
    const double low = index == 0 ? 0.0 : cumulative_[index - 1];
    const double weight = double(weights_[index]);
    // The largest float below 1 keeps the rescaled number inside [0, 1).
    const float rescaled = std::min(float((target - low) / weight), 0x1.fffffep-1f);
    return {index, float(weight / total_weight_), std::max(rescaled, 0.0f)};
  }

 private:
  std::vector<Emitter> emitters_;
  /// The median of the largest flux component over median_flux_particles of `emitter`'s
  /// particles (an unscrambled Halton sequence: the same for every frame), those that carry any.
  static float median_flux(const Emitter& emitter) {
    const Halton halton;
    std::vector<float> fluxes;
    for (int i = 0; i < median_flux_particles; ++i) {
      const auto k = std::uint64_t(i);
      const float flux = light_detail::largest_component(
          emitter.sample_emission(halton.sample(0, k), halton.sample(1, k), halton.sample(2, k), halton.sample(3, k)).flux);
      if (flux > 0.0f && std::isfinite(flux)) fluxes.push_back(flux);
    }
    if (fluxes.empty()) return std::numeric_limits<float>::infinity();
    const auto middle = fluxes.begin() + std::ptrdiff_t(fluxes.size() / 2);
    std::nth_element(fluxes.begin(), middle, fluxes.end());
    return *middle;
  }

  /// add, with the flux from which its particles are heavy (heavy_flux) given.
  void add_with_heavy(Emitter emitter, float heavy) {
    const glm::vec3 power = emitter.power();
    light_detail::check_emission(power, "LightSet: emitter power");
    const float weight = (power.x + power.y + power.z) / 3.0f;
    if (!(weight > 0.0f)) return;
    heavy_.push_back(heavy);
    emitters_.push_back(std::move(emitter));
    weights_.push_back(weight);
    total_weight_ += double(weight);
    cumulative_.push_back(total_weight_);
  }

  std::vector<float> heavy_;
  BounceOpenings bounce_openings_;
  std::vector<float> weights_;
  std::vector<double> cumulative_;
  double total_weight_ = 0.0;
};

}  // namespace igi
