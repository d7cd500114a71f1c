#pragma once
/// \file
/// `AtrousFilter`: the edge-avoiding à-trous wavelet filter of Dammertz et al. ("Edge-Avoiding
/// À-Trous Wavelet Transform for fast Global Illumination Filtering", HPG 2010), steered by
/// variance as in SVGF (Schied et al., HPG 2017), over the demodulated irradiance and the glossy
/// radiance of a tile.
///
/// 1. The S x S window of the discontinuity buffer first: it holds one pixel of every
///    interleaving set, so its same-surface mean removes the interleaving pattern exactly, and
///    the spread of the sets' luminances inside it estimates, per pixel, the variance of that
///    mean (the sets' variance over the number averaged).
/// 2. Then `passes` à-trous passes of a 3 x 3 kernel with taps `step` = 1, 2, 4, ... pixels apart,
///    each tap weighted by the kernel, the normals' agreement, the relative depth difference per
///    pixel of distance, the albedo difference and the luminance difference against the standard
///    deviation of the centre's mean (blurred over 3 x 3, as SVGF does), so that smooth regions
///    whose sets agree stay as they are, noisy ones are smoothed, and edges stop the filter. The
///    variance is filtered along (squared weights), so later passes trust their input more.
///
/// Every stage works on the part of the tile's buffer the later stages read, so the output of
/// an interior pixel depends only on the G-buffer within `border(S)` of it: with that border
/// rendered, the image does not depend on the tile size. The same holds stage by stage, which
/// lets one process's tiles compute each stage over their own pixels only and copy its border
/// from their neighbours' (StagedFilter). All stages run over SoA rows in SIMD, lane-wise, so the
/// result does not depend on the lane count either.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "igi/filters/filter.hpp"
#include "igi/filters/tile_filters.hpp"

namespace igi {

/// Settings of AtrousFilter.
struct AtrousSettings {
  /// À-trous passes after the S x S window, with steps 1, 2, ..., 2^(passes-1): each doubles the
  /// footprint and widens the border the pipeline renders around each tile by its step. Three:
  /// on Cornell (320 x 240, 16 VPLs, against a path-traced reference) relMSE falls 0.0253 (the
  /// window alone), 0.0239, 0.0222, 0.0202, 0.0185 for 0 to 4 passes while the border grows to
  /// 1, 2, 4, 8, 16 pixels; three keep it at a sixth of the default 48-pixel tile (a farm's tiles render it around them; one
  /// process's share theirs, TileEngine::render_frame).
  int passes = 3;
  /// The window's surface test (normals and depths admitted into the S x S mean), as the
  /// discontinuity buffer's: the mean is the discontinuity buffer's output.
  DiscontinuitySettings window{};
  /// 4: SVGF's sigma_l. A neighbour whose luminance differs from the centre's by k standard
  /// deviations of the centre's mean is weighted e^(-k/4): differences the sets' noise explains
  /// (k of 1 or 2) are smoothed, an edge in the lighting (a shadow, k >> 4) is kept. On Cornell
  /// 2 gave 4% more error, 8 and 16 2-3% less by blurring shadow edges further.
  float luminance_sigma = 4.0f;
  /// 2% per pixel of distance: the depth difference on one surface grows with the distance
  /// between the pixels, by below 2% of the depth per pixel on a plane seen up to 70 degrees
  /// off its normal at 160 pixels over a 40-degree field of view (finer images change less), so
  /// such a surface keeps weights above e^-1, while a step to an object 10% nearer or farther
  /// weighs e^-5 at one pixel.
  float depth_sigma = 0.02f;
  /// 0.25: albedo differences (Euclidean, over RGB) weigh e^(-(d/0.25)^2): texture detail of
  /// +-0.1 keeps 85% of its weight, a different material (Cornell's red against white walls,
  /// d = 0.95) none, since it usually marks another object whose light is its own.
  float albedo_sigma = 0.25f;
};

namespace filter_detail {

/// e^-t for t >= 0 on packets, relative error below 4e-6, zero beyond t = 87 (e^-87 = 2^-126 is
/// the smallest normal float) and for NaN. The library's exp runs lane by lane; this one as
/// e^-t = 2^-n e^u with n = round(t log2 e) and u = n ln2 - t in [-ln2 / 2, ln2 / 2], e^u
/// Taylor's series to u^5: the next term, below 0.347^6 / 720 = 2.4e-6, over e^u >= 0.707 is
/// 3.4e-6, and the series' float rounding adds a few 1e-8. u is n ln2 - t with ln2 in two parts
/// (Cody and Waite), its high part 12 bits so that n ln2_high is exact: from the float t log2 e
/// instead, u carried that product's rounding, up to 3.8e-6 near t = 87, and the error reached
/// 5.1e-6 where the compiler fused no multiply-adds (3.3e-6 where it did).
template <int W>
[[gnu::always_inline]] inline vfloat<W> exp_negative(const vfloat<W>& t) noexcept {
  const vfloat<W> one(1.0f);
  const vmask<W> representable = t <= vfloat<W>(87.0f);  // false for NaN too
  const vfloat<W> exponent = select(representable, max(t, vfloat<W>(0.0f)), vfloat<W>(0.0f));
  const vfloat<W> whole = floor(exponent * vfloat<W>(1.44269504f) + vfloat<W>(0.5f));
  // ln2 = 0.693145751953125 (0x3f317200: 12 significant bits, times n <= 126 exact) + 1.4286068e-6.
  const vfloat<W> u = (whole * vfloat<W>(0.693145751953125f) - exponent) + whole * vfloat<W>(1.42860682e-6f);
  const vfloat<W> e_u =
      one + u * (one + u * (vfloat<W>(1.0f / 2) + u * (vfloat<W>(1.0f / 6) + u * (vfloat<W>(1.0f / 24) + u * vfloat<W>(1.0f / 120)))));
  // 2^-n from the IEEE 754 exponent field (bias 127, 23 mantissa bits); n <= 126 keeps it normal.
  const vfloat<W> scale = bit_cast<float>((vint<W>(127) - convert<std::int32_t>(whole)) << 23);
  return keep(e_u * scale, representable);
}

/// Rec. 709 luminance of W colours.
template <int W>
[[gnu::always_inline]] inline vfloat<W> luminance(const vec3<W>& c) noexcept {
  return vfloat<W>(0.2126f) * c.x + vfloat<W>(0.7152f) * c.y + vfloat<W>(0.0722f) * c.z;
}

/// The filtered signal between two stages: irradiance, glossy radiance and the variance of each
/// one's luminance, over the whole tile buffer (only the part a stage computes is meaningful).
struct AtrousStage {
  Vec3Plane irradiance;          ///< Irradiance.
  Vec3Plane glossy;              ///< Glossy radiance.
  PixelPlane irradiance_variance;  ///< Variance of the irradiance's luminance.
  PixelPlane glossy_variance;      ///< Variance of the glossy radiance's luminance.
  int width = 0;                   ///< Pixels per row (the tile buffer's).
  /// Sizes the planes to `pixels` in rows of `row_width`, the glossy ones only with `glossy` (a
  /// diffuse tile's stages need half the memory); planes of another size are set to zero.
  void size(std::size_t pixels, int row_width, bool with_glossy) {
    if (irradiance_variance.size() != pixels || width != row_width) {
      width = row_width;
      irradiance.assign(pixels);
      irradiance_variance.assign(pixels);
      glossy.assign(0);
      glossy_variance.assign(0);
    }
    if (with_glossy && glossy_variance.size() != pixels) {
      glossy.assign(pixels);
      glossy_variance.assign(pixels);
    }
  }
};

/// Whether every component of every pixel of `planes` is zero.
inline bool all_zero(const Vec3Plane& planes) noexcept {
  for (const PixelPlane* plane : {&planes.x, &planes.y, &planes.z})
    if (!std::all_of(plane->data(), plane->data() + plane->size(), [](float v) { return v == 0.0f; })) return false;
  return true;
}

/// Buffer rows [y0, y1) and columns [x0, x1): the part of a tile's buffer a stage computes.
struct BufferRegion {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< Corners.
};

/// The interior of `g` grown by `reach` pixels on each side, clipped to the buffer.
inline BufferRegion grown_interior(const TileGBuffer& g, int reach) noexcept {
  return {std::max(g.border - reach, 0), std::max(g.border - reach, 0), std::min(g.width - g.border + reach, g.width),
          std::min(g.height - g.border + reach, g.height)};
}

/// Variance of the mean of `count` values with offsets `sum` and squared offsets `sum2` from a
/// reference: the spread of the values over the count (zero where count is zero).
template <int W>
[[gnu::always_inline]] inline vfloat<W> variance_of_mean(const vfloat<W>& sum, const vfloat<W>& sum2,
                                                         const vfloat<W>& count) noexcept {
  const vmask<W> some = count > vfloat<W>(0.0f);
  const vfloat<W> safe = select(some, count, vfloat<W>(1.0f));
  const vfloat<W> mean = sum / safe;
  return keep(max(sum2 / safe - mean * mean, vfloat<W>(0.0f)) / safe, some);
}

/// Stage 1 over `region`: the S x S same-surface mean of irradiance and glossy radiance and the
/// variance of each mean's luminance, into `out` (`Glossy` false: irradiance only, the glossy
/// planes are left as they are).
template <int W, bool Glossy>
void window_mean_and_variance(const TileGBuffer& g, int interleave, const SameSurface<W>& accept,
                              const BufferRegion& region, AtrousStage& out) {
  for (int cy = region.y0; cy < region.y1; ++cy)
    for (int cx = region.x0; cx < region.x1; cx += W) {
      const auto centre = std::ptrdiff_t(g.index(cx, cy));
      // Luminance offsets from the centre's own keep the second moment free of cancellation.
      const vfloat<W> centre_irradiance = luminance(load<W>(g.irradiance, centre));
      const vfloat<W> centre_glossy = luminance(load<W>(g.glossy, centre));
      vec3<W> irradiance(glm::vec3(0.0f)), glossy(glm::vec3(0.0f));
      vfloat<W> count(0.0f), irradiance_sum(0.0f), irradiance_sum2(0.0f), glossy_sum(0.0f), glossy_sum2(0.0f);
      for_each_in_window<W>(g, interleave, cx, cy, accept,
                            [&](std::ptrdiff_t neighbour, const vmask<W>& take) __attribute__((always_inline)) {
                              const vec3<W> e = load<W>(g.irradiance, neighbour);
                              irradiance.assign(irradiance + e, take);
                              count.assign(count + vfloat<W>(1.0f), take);
                              const vfloat<W> de = luminance(e) - centre_irradiance;
                              irradiance_sum.assign(irradiance_sum + de, take);
                              irradiance_sum2.assign(irradiance_sum2 + de * de, take);
                              if constexpr (Glossy) {
                                const vec3<W> s = load<W>(g.glossy, neighbour);
                                glossy.assign(glossy + s, take);
                                const vfloat<W> ds = luminance(s) - centre_glossy;
                                glossy_sum.assign(glossy_sum + ds, take);
                                glossy_sum2.assign(glossy_sum2 + ds * ds, take);
                              }
                            });
      store(average(irradiance, count), out.irradiance, centre);
      variance_of_mean(irradiance_sum, irradiance_sum2, count).store(out.irradiance_variance.data() + centre);
      if constexpr (Glossy) {
        store(average(glossy, count), out.glossy, centre);
        variance_of_mean(glossy_sum, glossy_sum2, count).store(out.glossy_variance.data() + centre);
      }
    }
}

/// The 3 x 3 kernel's weight per tap offset -1, 0, 1: the linear B-spline (1/4, 1/2, 1/4), the
/// smallest kernel whose à-trous cascade is smooth (its steps 1, 2, 4 add up to a 15-tap
/// B-spline-like kernel with no holes); 3 x 3 taps instead of Dammertz's 5 x 5 cost a third of
/// the work and half the border per pass.
inline constexpr float atrous_kernel[3] = {0.25f, 0.5f, 0.25f};

/// The exponent of the normals' agreement between unit normals `n` and `m`: 128 (1 - cos), so
/// that e^-x is SVGF's cos^128 (sigma_n = 128) to within 0.1% at 5 degrees (0.61) and 1.6% at
/// 10, below 1e-5 from 25 degrees on, where the discontinuity buffer cuts, and 0 for back-facing
/// normals (x >= 128); NaN for NaN normals, which exp_negative weighs 0. As an exponent it joins
/// the depth, albedo and luminance terms in the one exponential per tap, instead of seven
/// squarings of the clamped cosine.
template <int W>
[[gnu::always_inline]] inline vfloat<W> normal_exponent(const vec3<W>& n, const vec3<W>& m) noexcept {
  return vfloat<W>(128.0f) * (vfloat<W>(1.0f) - dot(n, m));
}

/// `variance` at the W pixels from `centre` on, blurred over the 3 x 3 kernel (SVGF's
/// pre-filter: one pixel's estimate from the S x S window is itself noisy); `columns[dx + 1]`
/// holds the lanes whose column offset dx = -1, 0, 1 lies in the buffer.
template <int W>
[[gnu::always_inline]] inline vfloat<W> blurred_variance(const PixelPlane& variance, const TileGBuffer& g, int cy,
                                                         std::ptrdiff_t centre, const vmask<W> (&columns)[3]) noexcept {
  vfloat<W> sum(0.0f), weights(0.0f);
#pragma GCC unroll 3
  for (int dy = -1; dy <= 1; ++dy) {
    if (cy + dy < 0 || cy + dy >= g.height) continue;
#pragma GCC unroll 3
    for (int dx = -1; dx <= 1; ++dx) {
      const vfloat<W> h(atrous_kernel[dx + 1] * atrous_kernel[dy + 1]);
      const std::ptrdiff_t at = centre + std::ptrdiff_t(dy) * g.width + dx;
      sum.assign(sum + h * load<W>(variance, at), columns[dx + 1]);
      weights.assign(weights + h, columns[dx + 1]);
    }
  }
  return sum / weights;  // the centre tap is always inside: weights > 0
}

/// One à-trous pass with taps `step` pixels apart over `region`, from `in` to `out` (`Glossy`
/// false: irradiance only, the glossy planes are left as they are).
template <int W, bool Glossy>
void atrous_pass(const TileGBuffer& g, const AtrousSettings& settings, int step, const BufferRegion& region,
                 const AtrousStage& in, AtrousStage& out) {
  const vfloat<W> zero(0.0f), one(1.0f);
  // Tiny against any standard deviation that matters, so a pixel whose sets all agree (zero
  // variance) admits only neighbours of its very luminance, without 0/0.
  const vfloat<W> no_variance(1e-20f);
  const vfloat<W> inverse_albedo_sigma2(1.0f / (settings.albedo_sigma * settings.albedo_sigma));
  // Every tap but the centre lies `step` pixels away (Chebyshev distance).
  const vfloat<W> inverse_step(1.0f / float(step));
  for (int cy = region.y0; cy < region.y1; ++cy)
    for (int cx = region.x0; cx < region.x1; cx += W) {
      const auto centre = std::ptrdiff_t(g.index(cx, cy));
      const vmask<W> centre_hit = load<W>(g.hit, centre) != zero;
      if (none(centre_hit)) {
        // A miss keeps its input, as when no tap is admitted.
        store(load<W>(in.irradiance, centre), out.irradiance, centre);
        load<W>(in.irradiance_variance, centre).store(out.irradiance_variance.data() + centre);
        if constexpr (Glossy) {
          store(load<W>(in.glossy, centre), out.glossy, centre);
          load<W>(in.glossy_variance, centre).store(out.glossy_variance.data() + centre);
        }
        continue;
      }
      // The lanes whose column offset -1, 0, +1 (the variance's blur) and -step, 0, +step (the
      // taps, for a hit centre) lie in the buffer.
      const vmask<W> adjacent[3] = {columns_inside<W>(cx - 1, g.width), columns_inside<W>(cx, g.width),
                                    columns_inside<W>(cx + 1, g.width)};
      const vmask<W> columns[3] = {centre_hit & columns_inside<W>(cx - step, g.width), centre_hit & adjacent[1],
                                   centre_hit & columns_inside<W>(cx + step, g.width)};
      const vec3<W> normal = load<W>(g.normal, centre), albedo = load<W>(g.albedo, centre);
      const vfloat<W> depth = load<W>(g.depth, centre);
      const vec3<W> centre_irradiance = load<W>(in.irradiance, centre);
      // Without Glossy the glossy planes may be unsized (AtrousStage::size): never read them.
      const vec3<W> centre_glossy = Glossy ? load<W>(in.glossy, centre) : vec3<W>(glm::vec3(0.0f));
      const vfloat<W> luminance_irradiance = luminance(centre_irradiance), luminance_glossy = luminance(centre_glossy);
      const vfloat<W> sigma(settings.luminance_sigma);
      const vfloat<W> inverse_spread_irradiance =
          one / (sigma * sqrt(blurred_variance<W>(in.irradiance_variance, g, cy, centre, adjacent)) + no_variance);
      vfloat<W> inverse_spread_glossy(0.0f);
      if constexpr (Glossy)
        inverse_spread_glossy = one / (sigma * sqrt(blurred_variance<W>(in.glossy_variance, g, cy, centre, adjacent)) + no_variance);
      // The depth test's scale per pixel of distance, one division per pixel instead of per tap.
      const vfloat<W> inverse_depth_scale = one / (vfloat<W>(settings.depth_sigma) * abs(depth));
      vec3<W> irradiance(glm::vec3(0.0f)), glossy(glm::vec3(0.0f));
      vfloat<W> weight_irradiance(0.0f), weight_glossy(0.0f), variance_irradiance(0.0f), variance_glossy(0.0f);
      // Adds a tap of `value` with `weight` (and its `variance`) on the lanes of `take` where the
      // weight is > 0. Weights are finite and >= 0: the kernel times e^-x in [0, 1], which is 0
      // for a NaN exponent (infinite or NaN normals, depths, albedos or irradiance).
      const auto add_tap = [&](const vec3<W>& value, const vfloat<W>& weight, const vfloat<W>& variance, const vmask<W>& take,
                               vec3<W>& sum, vfloat<W>& weights, vfloat<W>& variances) __attribute__((always_inline)) {
        const vmask<W> admitted = take & (weight > zero);
        sum.assign(sum + value * weight, admitted);
        weights.assign(weights + weight, admitted);
        variances.assign(variances + weight * weight * variance, admitted);
      };
      // Unrolled, the taps' offsets, kernel weights and the centre's special case are constants.
#pragma GCC unroll 3
      for (int ty = -1; ty <= 1; ++ty) {
        const int ny = cy + ty * step;
        if (ny < 0 || ny >= g.height) continue;
#pragma GCC unroll 3
        for (int tx = -1; tx <= 1; ++tx) {
          const vfloat<W> h(atrous_kernel[tx + 1] * atrous_kernel[ty + 1]);
          if (tx == 0 && ty == 0) {
            // The centre itself: its normal agrees with itself (a unit normal's 128 (1 - cos) is
            // 0 up to rounding), its albedo and luminance differences (no depth term at distance
            // 0) are zero, or NaN where its normal, albedo or radiance is not finite, so its
            // exponent is 0 (weight e^0 = 1 times the kernel) or NaN (no weight), as the general
            // tap below would find, without the exponential.
            const vfloat<W> self = dot(normal, normal);
            const vfloat<W> exponent = (self - self) + length_squared(albedo - albedo) * inverse_albedo_sigma2;
            const vfloat<W> we =
                keep(h, exponent + abs(luminance_irradiance - luminance_irradiance) * inverse_spread_irradiance == zero);
            add_tap(centre_irradiance, we, load<W>(in.irradiance_variance, centre), columns[1], irradiance, weight_irradiance,
                    variance_irradiance);
            if constexpr (Glossy) {
              const vfloat<W> ws =
                  keep(h, exponent + abs(luminance_glossy - luminance_glossy) * inverse_spread_glossy == zero);
              add_tap(centre_glossy, ws, load<W>(in.glossy_variance, centre), columns[1], glossy, weight_glossy,
                      variance_glossy);
            }
            continue;
          }
          const std::ptrdiff_t neighbour = centre + std::ptrdiff_t(ty * step) * g.width + tx * step;
          const vmask<W> take = columns[tx + 1] & (load<W>(g.hit, neighbour) != zero);
          if (none(take)) continue;
          // Normals, depth per pixel of distance, albedo and luminance in one exponent:
          // e^-(a+b+c+d) is one exponential per tap.
          vfloat<W> exponent = normal_exponent(normal, load<W>(g.normal, neighbour));
          exponent += abs(load<W>(g.depth, neighbour) - depth) * inverse_depth_scale * inverse_step;
          exponent += length_squared(load<W>(g.albedo, neighbour) - albedo) * inverse_albedo_sigma2;
          const vec3<W> e = load<W>(in.irradiance, neighbour);
          const vfloat<W> we = h * exp_negative(exponent + abs(luminance(e) - luminance_irradiance) * inverse_spread_irradiance);
          add_tap(e, we, load<W>(in.irradiance_variance, neighbour), take, irradiance, weight_irradiance, variance_irradiance);
          if constexpr (Glossy) {
            const vec3<W> s = load<W>(in.glossy, neighbour);
            const vfloat<W> ws = h * exp_negative(exponent + abs(luminance(s) - luminance_glossy) * inverse_spread_glossy);
            add_tap(s, ws, load<W>(in.glossy_variance, neighbour), take, glossy, weight_glossy, variance_glossy);
          }
        }
      }
      // No admitted tap (a miss, or a broken centre normal or depth): the input stays.
      const vmask<W> some_irradiance = weight_irradiance > zero;
      const vfloat<W> safe_irradiance = select(some_irradiance, weight_irradiance, one);
      store(select(some_irradiance, irradiance * (one / safe_irradiance), centre_irradiance), out.irradiance, centre);
      select(some_irradiance, variance_irradiance / (safe_irradiance * safe_irradiance), load<W>(in.irradiance_variance, centre))
          .store(out.irradiance_variance.data() + centre);
      if constexpr (Glossy) {
        const vmask<W> some_glossy = weight_glossy > zero;
        const vfloat<W> safe_glossy = select(some_glossy, weight_glossy, one);
        store(select(some_glossy, glossy * (one / safe_glossy), centre_glossy), out.glossy, centre);
        select(some_glossy, variance_glossy / (safe_glossy * safe_glossy), load<W>(in.glossy_variance, centre))
            .store(out.glossy_variance.data() + centre);
      }
    }
}

}  // namespace filter_detail

/// The stage outputs a tile of AtrousFilter keeps while its neighbours read them, in stages
/// (AtrousFilter::run_stage): stage k writes `buffers[k % 2]`, which stage k+1 of the tile and of
/// its neighbours read while stage k+1 writes the other.
struct AtrousTileStages {
  filter_detail::AtrousStage buffers[2];  ///< Ping-pong stage outputs, laid out as the tile's G-buffer.
  /// Whether this frame's stages filter glossy radiance (otherwise its glossy planes are stale
  /// or unsized, and its neighbours take zeros for them).
  bool glossy = false;
};

/// The edge-avoiding à-trous filter, variance-guided (see the file's comment): smoother than the
/// discontinuity buffer where few strong VPLs leave blotches, at the price of a wider border.
/// It runs whole per tile (`apply`, a farm's bordered tiles) or in stages over tiles that share
/// their borders (StagedFilter: one process's frame), with the same result.
class AtrousFilter {
 public:
  /// Its settings type.
  using Settings = AtrousSettings;
  /// What a tile keeps between stages.
  using TileStages = AtrousTileStages;
  /// Most passes: 5 reach 31 pixels, beyond any tile's use, and keep every row read within
  /// PixelPlane::padding (31 + 16 lanes < 64).
  static constexpr int max_passes = 5;

  /// Filter with `settings`; throws std::invalid_argument on passes outside 0..max_passes or a
  /// sigma that is not finite and > 0 (the window's thresholds are checked as DiscontinuityFilter's).
  explicit AtrousFilter(const Settings& settings = {}) : settings_(settings), window_(settings.window) {
    if (settings.passes < 0 || settings.passes > max_passes)
      throw std::invalid_argument("AtrousFilter: passes must be in 0.." + std::to_string(max_passes) + ", got " +
                                  std::to_string(settings.passes));
    for (const float sigma : {settings.luminance_sigma, settings.depth_sigma, settings.albedo_sigma})
      if (!(sigma > 0.0f) || !std::isfinite(sigma))
        throw std::invalid_argument("AtrousFilter: luminance_sigma, depth_sigma and albedo_sigma must be finite and > 0");
  }
  /// Policy name.
  static constexpr const char* name() noexcept { return "atrous"; }
  /// The settings in use.
  const Settings& settings() const noexcept { return settings_; }
  /// Pixels read around a tile: the S x S window's reach plus the passes' steps 1 + 2 + ... + 2^(passes-1).
  int border(int interleave) const noexcept { return window_border(interleave) + reach(settings_.passes); }

  /// Filters the interior of `gbuffer` into `out`; throws std::invalid_argument on inconsistent input.
  void apply(const TileGBuffer& gbuffer, int interleave, FilteredTile& out) const {
    filter_detail::prepare_filter("AtrousFilter", gbuffer, interleave, out);
    // Per-thread scratch: the filter is shared by the pipeline's threads, and tiles reuse the memory.
    thread_local filter_detail::AtrousStage stages[2];
    // Diffuse tiles (no glossy lobe in sight) skip the glossy planes: filtering zeros gives zeros,
    // already in `out`, and the work per tap halves.
    const bool glossy = !filter_detail::all_zero(gbuffer.glossy);
    size_stages(gbuffer, glossy, stages);
    for (int stage = 0; stage < stage_count(); ++stage) {
      // Stage k's output is read by the later passes within their steps' sum: 2^passes - 2^k.
      const filter_detail::BufferRegion region =
          filter_detail::grown_interior(gbuffer, reach(settings_.passes) - reach(stage));
      compute_stage(stage, gbuffer, interleave, glossy, region, stages[(stage + 1) % 2], stages[stage % 2]);
    }
    write_interior(gbuffer, stages[settings_.passes % 2], glossy, out);
  }

  /// Stages: the S x S window, then one per pass.
  int stage_count() const noexcept { return settings_.passes + 1; }
  /// Pixels around a tile of stage `stage - 1`'s output that stage `stage` > 0 reads: its taps'
  /// step 2^(stage-1), which covers the variance's 3 x 3 blur.
  int stage_reach(int stage) const noexcept { return stage > 0 ? 1 << (stage - 1) : 0; }
  /// Border of a tile's G-buffer and stage outputs when tiles share their borders: the window
  /// reads the G-buffer within window_border(S), pass k its geometry and stage k-1 within
  /// 2^(k-1), so the last pass's step (4 for three passes, against border()'s 8).
  int staged_border(int interleave) const noexcept {
    return std::max(window_border(interleave), stage_reach(settings_.passes));
  }
  /// Stage `stage` over the interior of `gbuffer` (StagedFilter); stage 0 checks the input
  /// (std::invalid_argument) and sizes `tile`'s buffers.
  void run_stage(int stage, const TileGBuffer& gbuffer, int interleave, TileStages& tile) const {
    if (stage == 0) {
      filter_detail::check_filter_input("AtrousFilter", gbuffer, interleave);
      tile.glossy = !filter_detail::all_zero(gbuffer.glossy);
      size_stages(gbuffer, tile.glossy, tile.buffers);
    }
    compute_stage(stage, gbuffer, interleave, tile.glossy, filter_detail::grown_interior(gbuffer, 0),
                  tile.buffers[(stage + 1) % 2], tile.buffers[stage % 2]);
  }
  /// Copies `block` of `neighbour`'s stage `stage` output into `tile`'s (StagedFilter): its glossy
  /// planes only where `tile` filters glossy radiance, zero from a neighbour that does not.
  void copy_stage(int stage, const TileStages& neighbour, const BlockCopy& block, TileStages& tile) const {
    const filter_detail::AtrousStage& from = neighbour.buffers[stage % 2];
    filter_detail::AtrousStage& to = tile.buffers[stage % 2];
    const int from_width = from.width, to_width = to.width;
    copy_block(from.irradiance, from_width, to.irradiance, to_width, block);
    copy_block(from.irradiance_variance, from_width, to.irradiance_variance, to_width, block);
    if (!tile.glossy) return;
    if (neighbour.glossy) {
      copy_block(from.glossy, from_width, to.glossy, to_width, block);
      copy_block(from.glossy_variance, from_width, to.glossy_variance, to_width, block);
      return;
    }
    // A tile whose G-buffer (border included) has no glossy radiance would have filtered it to
    // exactly zero: zeros in, zero variance, and a weighted mean of zeros.
    for (int row = 0; row < block.rows; ++row)
      for (PixelPlane* plane : {&to.glossy.x, &to.glossy.y, &to.glossy.z, &to.glossy_variance}) {
        float* out = plane->data() + std::size_t(block.y + row) * std::size_t(to_width) + std::size_t(block.x);
        std::fill_n(out, block.columns, 0.0f);
      }
  }
  /// The last stage's result for the interior of `gbuffer` into `out` (StagedFilter).
  void finish(const TileGBuffer& gbuffer, const TileStages& tile, FilteredTile& out) const {
    filter_detail::prepare_filter("AtrousFilter", gbuffer, 1, out);  // 1: stage 0 checked the interleave
    write_interior(gbuffer, tile.buffers[settings_.passes % 2], tile.glossy, out);
  }

 private:
  /// Sizes `stages` to `gbuffer`'s pixels (their glossy planes too with `glossy`), zero where
  /// their size changes. They are never cleared otherwise: each stage writes every pixel the
  /// next one reads (see the file's comment), so nothing a previous tile left reaches the image.
  static void size_stages(const TileGBuffer& gbuffer, bool glossy, filter_detail::AtrousStage (&stages)[2]) {
    const std::size_t pixels = std::size_t(gbuffer.width) * std::size_t(gbuffer.height);
    for (auto& stage : stages) stage.size(pixels, gbuffer.width, glossy);
  }
  /// Stage `stage` over `region`: the window from the G-buffer (stage 0) or pass `stage - 1`
  /// from `in`, into `out`, with the glossy radiance or (`glossy` false) without.
  void compute_stage(int stage, const TileGBuffer& gbuffer, int interleave, bool glossy,
                     const filter_detail::BufferRegion& region, const filter_detail::AtrousStage& in,
                     filter_detail::AtrousStage& out) const {
    constexpr int W = filter_detail::row_lanes;
    const auto run = [&]<bool Glossy>() {
      if (stage == 0) {
        const filter_detail::SameSurface<W> same_surface{&gbuffer, window_.cos_max_angle(),
                                                         settings_.window.max_relative_depth};
        filter_detail::window_mean_and_variance<W, Glossy>(gbuffer, interleave, same_surface, region, out);
      } else {
        filter_detail::atrous_pass<W, Glossy>(gbuffer, settings_, 1 << (stage - 1), region, in, out);
      }
    };
    if (glossy)
      run.template operator()<true>();
    else
      run.template operator()<false>();
  }
  /// The interior of `result` into `out` (the glossy planes only when `glossy`: they stay zero otherwise).
  static void write_interior(const TileGBuffer& gbuffer, const filter_detail::AtrousStage& result, bool glossy,
                             FilteredTile& out) {
    constexpr int W = filter_detail::row_lanes;
    for (int y = 0; y < out.height; ++y)
      for (int x = 0; x < out.width; x += W) {
        const auto from = std::ptrdiff_t(gbuffer.index(x + gbuffer.border, y + gbuffer.border));
        const auto to = std::ptrdiff_t(y) * out.width + x;
        // Misses get zero, as in the discontinuity buffer (the passes leave a miss's input, already zero).
        filter_detail::store(filter_detail::load<W>(result.irradiance, from), out.irradiance, to);
        if (glossy) filter_detail::store(filter_detail::load<W>(result.glossy, from), out.glossy, to);
      }
  }

  /// Sum of the steps of `passes` passes: 1 + 2 + ... + 2^(passes-1).
  static constexpr int reach(int passes) noexcept { return (1 << passes) - 1; }

  Settings settings_;
  DiscontinuityFilter window_;  ///< Checks the window's thresholds and holds their cosine.
};

}  // namespace igi
