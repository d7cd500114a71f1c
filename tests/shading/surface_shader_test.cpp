// Surface shaders: texture sampling, the glTF material mapping, noise, procedural patterns and
// the scalar adapter.

#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "igi/shading/gltf_material_shader.hpp"
#include "igi/shading/noise.hpp"
#include "igi/shading/procedural_shaders.hpp"
#include "igi/shading/scalar_shader_adapter.hpp"
#include "igi/shading/texture_sampling.hpp"
#include "shading/shading_support.hpp"

using namespace igi;
using namespace igi::testing;

namespace {

// A 2x2 texture: red, green / blue, white (top row first), alpha 255, 0 / 255, 128.
Texture checker(bool srgb) {
  Texture t;
  t.name = "checker";
  t.width = 2;
  t.height = 2;
  t.srgb = srgb;
  t.texels = {255, 0, 0, 255, 0, 255, 0, 0, 0, 0, 255, 255, 255, 255, 255, 128};
  return t;
}

// W hits on a floor facing +y at positions along x, front faces, material 0.
SurfaceHit<W> floor_hits(float spacing, float y = 0.0f) {
  SurfaceHit<W> hit;
  for (int i = 0; i < W; ++i) {
    hit.position.set(i, {float(i) * spacing, y, 0.37f * float(i)});
    hit.u.set(i, 0.25f);
    hit.v.set(i, 0.25f);
  }
  hit.geometric_normal = vec3<W>(glm::vec3(0, 1, 0));
  hit.shading_normal = hit.geometric_normal;
  hit.wo = hit.geometric_normal;
  hit.front_face = vmask<W>(true);
  return hit;
}

/// glTF's dielectric reflectance at normal incidence, ((1.5 - 1) / (1.5 + 1))^2 for its default ior.
constexpr float gltf_f0 = 0.04f;
/// What a dielectric's diffuse part keeps under that layer seen head-on.
constexpr float dielectric_diffuse = 1.0f - gltf_f0;

bool finite(const vec3<W>& v) { return all(isfinite(v.x) & isfinite(v.y) & isfinite(v.z)); }

// A scene of one linear (not sRGB) `width` x `height` RGBA texture and one mesh of material 0,
// for the textures that hold no colour (metallic-roughness, normals).
Scene linear_texture_scene(int width, int height, std::vector<std::uint8_t> texels) {
  Scene scene;
  scene.textures.push_back({.name = "linear", .width = width, .height = height, .texels = std::move(texels), .srgb = false});
  Mesh mesh;
  mesh.material = 0;
  scene.meshes.push_back(mesh);
  return scene;
}

}  // namespace

TEST_CASE("texture: sRGB table and bilinear lookups with repeat wrapping", "[shading][texture]") {
  const auto& table = srgb_to_linear_table();
  CHECK(table[0] == 0.0f);
  CHECK(table[255] == Approx(1.0f));
  CHECK(table[128] == Approx(0.2158605f).epsilon(1e-5));  // IEC 61966-2-1 value of 128/255
  for (int i = 1; i < 256; ++i) CHECK(table[std::size_t(i)] > table[std::size_t(i - 1)]);

  const Texture t = checker(false);
  // Texel centres give the texels exactly; v = 0 is the top row.
  CHECK(sample_bilinear(t, {0.25f, 0.25f}) == glm::vec4(1, 0, 0, 1));
  CHECK(sample_bilinear(t, {0.75f, 0.75f}) == glm::vec4(1, 1, 1, 128.0f / 255.0f));
  // Half way between the two top texels.
  const glm::vec4 mid = sample_bilinear(t, {0.5f, 0.25f});
  CHECK(mid.x == Approx(0.5f));
  CHECK(mid.y == Approx(0.5f));
  // Repeat: u + 1 and u - 3 read the same; the edge blends with the opposite side.
  CHECK(sample_bilinear(t, {1.25f, 0.25f}) == sample_bilinear(t, {0.25f, 0.25f}));
  CHECK(sample_bilinear(t, {-2.75f, 0.25f}) == sample_bilinear(t, {0.25f, 0.25f}));
  const glm::vec4 edge = sample_bilinear(t, {0.0f, 0.25f});
  CHECK(edge.x == Approx(0.5f));
  // Garbage coordinates and empty textures do not crash.
  const glm::vec4 nan = sample_bilinear(t, {std::numeric_limits<float>::quiet_NaN(), 1e30f});
  CHECK(std::isfinite(nan.x));
  CHECK(sample_bilinear(Texture{}, {0.5f, 0.5f}) == glm::vec4(1.0f));
  // sRGB decoding: 255 -> 1 either way, alpha never decoded.
  CHECK(sample_bilinear(checker(true), {0.75f, 0.75f}).w == Approx(128.0f / 255.0f));
}

TEST_CASE("texture: the alpha-only lookup reads what the full lookup's alpha reads", "[shading][texture]") {
  // Irregular alpha (and colour) over an odd-sized texture, so that every texel and weight differs.
  Texture t;
  t.width = 7;
  t.height = 5;
  for (int i = 0; i < t.width * t.height * 4; ++i) t.texels.push_back(std::uint8_t((i * 97 + 13) % 256));
  std::mt19937 random(3);
  std::uniform_real_distribution<float> coordinate(-3.0f, 3.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN(), infinity = std::numeric_limits<float>::infinity();
  // The same arithmetic, up to the compiler fusing a multiply and an add into one rounding in one
  // of the two and not the other: a few units in the last place of values in [0, 1].
  const float rounding = 4.0f * std::numeric_limits<float>::epsilon();
  for (const bool srgb : {false, true}) {
    t.srgb = srgb;
    for (int k = 0; k < 200; ++k) {
      const glm::vec2 uv(coordinate(random), coordinate(random));
      CHECK(std::abs(sample_bilinear_alpha(t, uv) - sample_bilinear(t, uv).a) <= rounding);
    }
    for (const glm::vec2 uv : {glm::vec2(nan, 0.3f), glm::vec2(0.2f, infinity), glm::vec2(1e30f, -1e30f), glm::vec2(1.0f, 0.0f)})
      CHECK(std::abs(sample_bilinear_alpha(t, uv) - sample_bilinear(t, uv).a) <= rounding);
    // Packets: lanes off the mask are zero, the others their own point's alpha.
    vfloat<8> u, v;
    vmask<8> mask;
    for (int i = 0; i < 8; ++i) {
      u.set(i, coordinate(random));
      v.set(i, coordinate(random));
      mask.set(i, i % 3 != 1);
    }
    const vfloat<8> alpha = sample_bilinear_alpha(t, u, v, mask);
    const TexelPacket<8> full = sample_bilinear(t, u, v, mask);
    for (int i = 0; i < 8; ++i)
      CHECK(std::abs(alpha[i] - full.a[i]) <= rounding);
    for (int i = 1; i < 8; i += 3) CHECK(alpha[i] == 0.0f);
  }
  CHECK(sample_bilinear_alpha(Texture{}, {0.5f, 0.5f}) == 1.0f);
}

namespace {

// A `width` x `height` texture of `srgb` texels from `value(x, y, channel)`.
template <class Value>
Texture made_texture(int width, int height, bool srgb, const Value& value) {
  Texture t;
  t.name = "made";
  t.width = width;
  t.height = height;
  t.srgb = srgb;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 4; ++c) t.texels.push_back(std::uint8_t(value(x, y, c)));
  return t;
}

// Mean linear RGBA of a texture's texels.
glm::dvec4 linear_mean(const Texture& t) {
  glm::dvec4 sum(0.0);
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x) sum += glm::dvec4(texel(t, x, y));
  return sum / double(t.width * t.height);
}

}  // namespace

TEST_CASE("texture: mip chains keep the linear mean, halve down to 1 x 1 and read trilinearly", "[shading][texture]") {
  // Every 8-bit code is its own nearest code, and a linear value goes to the code nearest it.
  const auto& table = srgb_to_linear_table();
  for (int code = 0; code < 256; ++code) CHECK(nearest_srgb_code(table[std::size_t(code)]) == code);
  CHECK(nearest_srgb_code(0.5f) == 188);  // linear 0.5 is sRGB 0.735 (187.5 / 255 rounds to 188)
  CHECK(nearest_srgb_code(-1.0f) == 0);
  CHECK(nearest_srgb_code(2.0f) == 255);

  // Odd sizes: 37 x 11 -> 18 x 5 -> 9 x 2 -> 4 x 1 -> 2 x 1 -> 1 x 1, each level box-filtered
  // from the one before with every source texel's full weight, so each keeps the linear mean up
  // to 8-bit rounding (half an sRGB step, below 0.004 in linear at these values, per level).
  std::mt19937 random(5);
  for (const bool srgb : {true, false}) {
    const Texture noisy = made_texture(37, 11, srgb, [&](int, int, int) { return int(random() % 256); });
    const TextureMips mips(noisy);
    const int sizes[][2] = {{37, 11}, {18, 5}, {9, 2}, {4, 1}, {2, 1}, {1, 1}};
    REQUIRE(mips.count() == 6);
    const glm::dvec4 mean = linear_mean(noisy);
    for (int k = 0; k < mips.count(); ++k) {
      INFO("srgb " << srgb << ", level " << k);
      CHECK(mips.level(k).width == sizes[k][0]);
      CHECK(mips.level(k).height == sizes[k][1]);
      CHECK(mips.level(k).srgb == srgb);
      const glm::dvec4 level_mean = linear_mean(mips.level(k));
      for (int c = 0; c < 4; ++c) CHECK(std::abs(level_mean[c] - mean[c]) < 0.004 * (k + 1));
    }
  }
  // A black and white checkerboard of single texels halves to grey: linear 0.5, sRGB 188.
  const Texture board = made_texture(64, 64, true, [](int x, int y, int c) { return c == 3 || (x + y) % 2 ? 255 : 0; });
  const TextureMips mips(board);
  REQUIRE(mips.count() == 7);
  for (int k = 1; k < mips.count(); ++k)
    for (int c = 0; c < 3; ++c) CHECK(int(mips.level(k).texels[std::size_t(c)]) == 188);

  // A footprint of f texels reads the levels whose texels are f / sqrt(3) wide (sample_filtered's
  // comment). At most sqrt(3) texels, zero, NaN or infinite read level 0 exactly as sample_bilinear.
  const glm::vec2 uv(0.3172f, 0.6611f);
  const float sqrt3 = std::sqrt(3.0f);
  for (const float footprint : {0.0f, 1.0f / 64.0f, 0.99f * sqrt3 / 64.0f, std::numeric_limits<float>::quiet_NaN(),
                                std::numeric_limits<float>::infinity(), -1.0f})
    CHECK(sample_filtered(mips, uv, footprint) == sample_bilinear(board, uv));
  // 2 sqrt(3) texels read level 1 alone (to float rounding of the level); 4 sqrt(3) level 2;
  // 2^1.5 sqrt(3) half way between.
  CHECK(glm::length(sample_filtered(mips, uv, 2.0f * sqrt3 / 64.0f) - sample_bilinear(mips.level(1), uv)) < 1e-4f);
  CHECK(glm::length(sample_filtered(mips, uv, 4.0f * sqrt3 / 64.0f) - sample_bilinear(mips.level(2), uv)) < 1e-4f);
  const glm::vec4 between = sample_filtered(mips, uv, std::exp2(1.5f) * sqrt3 / 64.0f);
  const glm::vec4 halfway = 0.5f * (sample_bilinear(mips.level(1), uv) + sample_bilinear(mips.level(2), uv));
  CHECK(glm::length(between - halfway) < 1e-3f);
  // Wider than the texture: its 1 x 1 mean.
  CHECK(sample_filtered(mips, uv, 10.0f) == sample_bilinear(mips.level(6), uv));
  // Where the checks are finer than the footprint, any point reads their mean, where a point
  // lookup reads black or white (or their bilinear blend).
  double filtered_error = 0.0, point_error = 0.0;
  for (int k = 0; k < 1000; ++k) {
    const glm::vec2 at(float(random()) / float(random.max()), float(random()) / float(random.max()));
    filtered_error = std::max(filtered_error, double(std::abs(sample_filtered(mips, at, 4.0f * sqrt3 / 64.0f).x - table[188])));
    point_error = std::max(point_error, double(std::abs(sample_bilinear(board, at).x - table[188])));
  }
  CHECK(filtered_error < 1e-6);
  CHECK(point_error > 0.4);
  // An empty texture has level 0 alone and reads white, as sample_bilinear.
  const Texture empty;
  const TextureMips none(empty);
  CHECK(none.count() == 1);
  CHECK(sample_filtered(none, uv, 0.5f) == glm::vec4(1.0f));
}

TEST_CASE("GltfMaterialShader: factors, texture, cut-outs, metal, mirror, glass and emission", "[shading][gltf]") {
  Scene scene;
  scene.textures.push_back(checker(true));
  Mesh mesh;
  mesh.material = 0;
  scene.meshes.push_back(mesh);
  Material textured{.name = "textured", .base_color = {0.5f, 1.0f, 1.0f, 1.0f}, .base_color_texture = 0, .metallic = 0.0f};
  textured.alpha_mode = AlphaMode::mask;
  scene.materials.push_back(textured);
  scene.materials.push_back({.name = "gold", .base_color = {1.0f, 0.8f, 0.3f, 1.0f}, .metallic = 1.0f, .roughness = 0.5f});
  scene.materials.push_back({.name = "chrome", .base_color = {0.9f, 0.9f, 0.9f, 1.0f}, .metallic = 1.0f, .roughness = 0.0f});
  scene.materials.push_back({.name = "glass", .base_color = {1, 1, 1, 1}, .metallic = 0.0f, .transmission = 1.0f, .ior = 1.33f});
  scene.materials.push_back({.name = "lamp", .base_color = {1, 1, 1, 1}, .metallic = 0.0f, .emission = {4, 3, 2}});

  const GltfMaterialShader shader(scene);
  STATIC_REQUIRE(SurfaceShader<GltfMaterialShader, W>);
  SurfaceHit<W> hit = floor_hits(0.1f);
  for (int i = 0; i < 5; ++i) hit.material.set(i, i);
  hit.material.set(5, 4);
  hit.front_face.set(5, false);  // the lamp's back face does not emit
  hit.material.set(6, 0);
  hit.u.set(6, 0.75f);  // the texel with alpha 0: cut out
  vmask<W> mask(true);
  mask.set(7, false);
  const BrdfParameters<W> p = shader.shade(hit, mask);

  // Red texel (decoded 1, 0, 0) times factor 0.5, under glTF's 4% specular layer (seen head-on,
  // the hits' wo is their normal): albedo (0.5 x 0.96, 0, 0), glossy 0.04, opaque.
  CHECK(glm::length(p.albedo[0] - glm::vec3(0.5f * dielectric_diffuse, 0.0f, 0.0f)) < 1e-6f);
  CHECK(glm::length(p.glossy[0] - glm::vec3(gltf_f0)) < 1e-6f);
  CHECK(p.opaque[0]);
  CHECK_FALSE(p.opaque[6]);
  // Gold: no diffuse part, glossy in its colour with exponent 2 / 0.25^2 - 2 = 30.
  CHECK(p.albedo[1] == glm::vec3(0.0f));
  CHECK(glm::length(p.glossy[1] - glm::vec3(1.0f, 0.8f, 0.3f)) < 1e-6f);
  CHECK(p.shininess[1] == Approx(30.0f));
  // Chrome is smoother than the mirror threshold: a mirror.
  CHECK(glm::length(p.mirror[2] - glm::vec3(0.9f)) < 1e-6f);
  CHECK(p.glossy[2] == glm::vec3(0.0f));
  // Glass: all transmission, no diffuse, its ior.
  CHECK(p.transmission[3] == 1.0f);
  CHECK(p.albedo[3] == glm::vec3(0.0f));
  CHECK(p.ior[3] == Approx(1.33f));
  // Emission on the front face only.
  CHECK(p.emission[4] == glm::vec3(4, 3, 2));
  CHECK(p.emission[5] == glm::vec3(0.0f));
  // Normals are the shading normals; the inactive lane is zero.
  CHECK(p.normal[0] == glm::vec3(0, 1, 0));
  CHECK(p.albedo[7] == glm::vec3(0.0f));
  CHECK(p.normal[7] == glm::vec3(0.0f));
  CHECK_FALSE(p.opaque[7]);

  // A footprint wider than the 2 x 2 texture reads its 1 x 1 level: the four texels' linear mean
  // (red, green, blue, white: 0.5 in every channel up to 8-bit rounding), still times the factor.
  SurfaceHit<W> wide = hit;
  wide.texture_footprint = vfloat<W>(4.0f);
  const BrdfParameters<W> blurred = shader.shade(wide, mask);
  const float grey = srgb_to_linear_table()[nearest_srgb_code(0.5f)];
  CHECK(glm::length(blurred.albedo[0] - glm::vec3(0.5f * grey, grey, grey) * dielectric_diffuse) < 1e-6f);
  // Cut-outs still test the alpha at the ray's point (0 there), not the mean (0.63, above the
  // cut-off 0.5): seen from afar the lane stays cut out, so a mask's coverage holds on average.
  CHECK_FALSE(blurred.opaque[6]);
  CHECK(blurred.opaque[0]);

  // Bad references are errors with a message.
  SurfaceHit<W> bad = hit;
  bad.material.set(0, 42);
  CHECK_THROWS_WITH(shader.shade(bad, mask), Catch::Contains("material 42"));
  Scene broken = scene;
  broken.materials[0].base_color_texture = 9;
  CHECK_THROWS_WITH(GltfMaterialShader(broken), Catch::Contains("texture 9"));
}

TEST_CASE("GltfMaterialShader: metallic-roughness textures scale the factors, linearly, at the footprint", "[shading][gltf]") {
  // 2 x 2: green (roughness) 64, 255 / 128, 0; blue (metallic) 0, 255 / 51, 204.
  Scene scene = linear_texture_scene(2, 2, {0, 64, 0, 255, 0, 255, 255, 255, 0, 128, 51, 255, 0, 0, 204, 255});
  const Texture& texture = scene.textures[0];
  const glm::vec4 base{0.8f, 0.6f, 0.4f, 1.0f};
  scene.materials.push_back(
      {.name = "textured", .base_color = base, .metallic = 0.75f, .roughness = 0.9f, .metallic_roughness_texture = 0});
  const GltfMaterialShader shader(scene);

  // Each lane at one texel's centre; the same material with the factors times that texel's
  // channels (linear: code / 255) must shade identically, lobe, mirror and albedo alike.
  const float centres[4][2] = {{0.25f, 0.25f}, {0.75f, 0.25f}, {0.25f, 0.75f}, {0.75f, 0.75f}};
  SurfaceHit<W> hit = floor_hits(0.1f);
  vmask<W> mask(false);
  Scene expected_scene = scene;
  expected_scene.materials.clear();
  expected_scene.textures.clear();
  for (int texel = 0; texel < 4; ++texel) {
    hit.u.set(texel, centres[texel][0]);
    hit.v.set(texel, centres[texel][1]);
    hit.material.set(texel, 0);
    mask.set(texel, true);
    const std::uint8_t* rgba = &texture.texels[std::size_t(texel) * 4];
    expected_scene.materials.push_back({.name = "factors",
                                        .base_color = base,
                                        .metallic = 0.75f * (float(rgba[2]) / 255.0f),
                                        .roughness = 0.9f * (float(rgba[1]) / 255.0f)});
  }
  const GltfMaterialShader expected_shader(expected_scene);
  SurfaceHit<W> expected_hit = hit;
  for (int texel = 0; texel < 4; ++texel) expected_hit.material.set(texel, texel);
  const BrdfParameters<W> p = shader.shade(hit, mask);
  const BrdfParameters<W> q = expected_shader.shade(expected_hit, mask);
  for (int lane = 0; lane < 4; ++lane) {
    INFO("texel " << lane);
    CHECK(glm::length(p.albedo[lane] - q.albedo[lane]) < 1e-6f);
    CHECK(glm::length(p.glossy[lane] - q.glossy[lane]) < 1e-6f);
    CHECK(glm::length(p.mirror[lane] - q.mirror[lane]) < 1e-6f);
    CHECK(p.shininess[lane] == Approx(q.shininess[lane]).epsilon(1e-5));
  }
  // Texel 0: roughness 0.9 x 64/255 = 0.226, metallic 0: the base colour under the 4% layer.
  CHECK(glm::length(p.albedo[0] - glm::vec3(base) * dielectric_diffuse) < 1e-6f);
  CHECK(glm::length(p.glossy[0] - glm::vec3(gltf_f0)) < 1e-6f);
  // Texel 3: roughness 0 (below the mirror threshold), metallic 0.75 x 0.8 = 0.6: a mirror of 60%
  // the base colour plus 40% of the dielectric's 4%.
  CHECK(glm::length(p.mirror[3] - (glm::vec3(base) * 0.6f + glm::vec3(0.4f * gltf_f0))) < 1e-6f);
  CHECK(glm::length(p.albedo[3] - glm::vec3(base) * 0.4f * dielectric_diffuse) < 1e-6f);
  // Texel 1: metallic 0.75, roughness 0.9: exponent 2 / 0.9^4 - 2.
  CHECK(p.shininess[1] == Approx(2.0f / std::pow(0.9f, 4.0f) - 2.0f).epsilon(1e-5));

  // Read as linear, not sRGB: code 128 is roughness 0.9 x 0.502, where sRGB would give 0.9 x 0.216.
  const float roughness = 0.9f * 128.0f / 255.0f;
  const float alpha = roughness * roughness;
  CHECK(p.shininess[2] == Approx(2.0f / (alpha * alpha) - 2.0f).epsilon(1e-5));

  // A footprint wider than the texture reads the 1 x 1 level: the channels' means scale the factors.
  SurfaceHit<W> wide = hit;
  wide.texture_footprint = vfloat<W>(4.0f);
  const BrdfParameters<W> blurred = shader.shade(wide, mask);
  const TextureMips chain(texture);
  REQUIRE(chain.count() == 2);
  const float mean_metallic = 0.75f * float(chain.level(1).texels[2]) / 255.0f;
  // The mean of 0, 1, 0.2 and 0.8 is 0.5, code 127.5, which the 8-bit level stores within a code.
  CHECK(mean_metallic == Approx(0.75f * 0.5f).margin(0.75f / 255.0f));
  for (int lane = 0; lane < 4; ++lane)
    CHECK(glm::length(blurred.albedo[lane] - glm::vec3(base) * (1.0f - mean_metallic) * dielectric_diffuse) < 1e-6f);

  // A texture the scene lacks is an error with a message.
  Scene broken = scene;
  broken.materials[0].metallic_roughness_texture = 3;
  CHECK_THROWS_WITH(GltfMaterialShader(broken), Catch::Contains("texture 3"));
}

TEST_CASE("GltfMaterialShader: normal textures tilt the normal in the uv tangent frame, as glTF orients it",
          "[shading][gltf]") {
  // 4 x 1: flat (128, 128, 255), tilted 45 degrees towards +x of the map (218, 128, 218),
  // towards +y (128, 218, 218), and pointing into the surface (128, 128, 0).
  Scene scene = linear_texture_scene(4, 1, {128, 128, 255, 255, 218, 128, 218, 255, 128, 218, 218, 255, 128, 128, 0, 255});
  Material bumpy{.name = "bumpy", .metallic = 0.0f};
  bumpy.normal_texture = 0;
  scene.materials.push_back(bumpy);
  Material flattened = bumpy;
  flattened.normal_scale = 0.0f;
  scene.materials.push_back(flattened);
  const GltfMaterialShader shader(scene);

  // A floor facing +y, u along +x, v along +z (its image's up is -z); lane i reads texel i % 4.
  SurfaceHit<W> hit = floor_hits(0.1f);
  hit.dpdu = vec3<W>(glm::vec3(2.0f, 0.0f, 0.0f));
  hit.dpdv = vec3<W>(glm::vec3(0.0f, 0.0f, 3.0f));
  for (int i = 0; i < W; ++i) {
    hit.u.set(i, (float(i % 4) + 0.5f) / 4.0f);
    hit.v.set(i, 0.5f);
    hit.material.set(i, 0);
  }
  // Lane 4: mirrored uvs (v along -z: the image's up is +z). Lane 5: the back face of the floor,
  // seen from below. Lane 6: no uv frame. Lane 7: scale 0.
  hit.dpdv.set(4, {0.0f, 0.0f, -3.0f});
  hit.u.set(4, 2.5f / 4.0f);
  hit.shading_normal.set(5, {0.0f, -1.0f, 0.0f});
  hit.geometric_normal.set(5, {0.0f, -1.0f, 0.0f});
  hit.wo.set(5, {0.0f, -1.0f, 0.0f});
  hit.front_face.set(5, false);
  hit.u.set(5, 1.5f / 4.0f);
  hit.dpdu.set(6, glm::vec3(0.0f));
  hit.u.set(6, 1.5f / 4.0f);
  hit.material.set(7, 1);
  hit.u.set(7, 1.5f / 4.0f);
  const BrdfParameters<W> p = shader.shade(hit, vmask<W>(true));

  // 8-bit texels: 128 and 218 decode to 2 c / 255 - 1 = 0.0039 and 0.7098, which the expected
  // normals use too; 1e-5 is float rounding of unit vectors.
  const auto decode = [](float code) { return 2.0f * code / 255.0f - 1.0f; };
  const auto near = [](const glm::vec3& a, const glm::vec3& b) { return glm::length(a - b) < 1e-5f; };
  const float flat = decode(128.0f), tilt = decode(218.0f);
  // Map axes on the floor: x -> +x (dp/du), y -> -z (against dp/dv), z -> +y.
  CHECK(near(p.normal[0], glm::normalize(glm::vec3(flat, decode(255.0f), -flat))));
  CHECK(near(p.normal[1], glm::normalize(glm::vec3(tilt, tilt, -flat))));
  CHECK(near(p.normal[2], glm::normalize(glm::vec3(flat, tilt, -tilt))));
  // Mirrored: the map's +y still points against dp/dv, now +z.
  CHECK(near(p.normal[4], glm::normalize(glm::vec3(flat, tilt, tilt))));
  // Back face: the front face's tilted normal, turned round.
  CHECK(near(p.normal[5], -glm::normalize(glm::vec3(tilt, tilt, -flat))));
  // No frame, or scale 0: the shading normal (scale 0 keeps only the map's z).
  CHECK(near(p.normal[6], glm::vec3(0.0f, 1.0f, 0.0f)));
  CHECK(near(p.normal[7], glm::vec3(0.0f, 1.0f, 0.0f)));
  // The tilt stays within 0.01 of 45 degrees, as the texel says.
  CHECK(std::acos(p.normal[1].y) == Approx(0.25f * 3.14159265f).margin(0.01f));

  // A texel pointing into the surface gives a normal that faces away from wo: shading falls
  // back to the geometric normal rather than lighting the floor from behind.
  CHECK(near(p.normal[3], glm::normalize(glm::vec3(flat, -1.0f, -flat))));
  CHECK(near(shading_frame_normal(hit, p)[3], glm::vec3(0.0f, 1.0f, 0.0f)));

  Scene broken = scene;
  broken.materials[0].normal_texture = 5;
  CHECK_THROWS_WITH(GltfMaterialShader(broken), Catch::Contains("texture 5"));
}

TEST_CASE("GltfMaterialShader: each texture is read through its KHR_texture_transform, footprint, cut-outs and normal "
          "frame included", "[shading][gltf]") {
  Scene scene;
  scene.textures.push_back(checker(true));
  scene.textures.push_back(linear_texture_scene(4, 1, {128, 128, 255, 255, 218, 128, 218, 255, 128, 218, 218, 255, 128, 128, 0, 255})
                               .textures[0]);
  Mesh mesh;
  mesh.material = 0;
  scene.meshes.push_back(mesh);
  const UvTransform transform = UvTransform::from({0.25f, -0.5f}, 0.7f, {2.0f, 0.5f});
  Material transformed{.name = "transformed", .base_color_texture = 0, .metallic = 0.0f};
  transformed.base_color_transform = transform;
  transformed.alpha_mode = AlphaMode::mask;
  transformed.normal_texture = 1;
  transformed.normal_transform = transform;
  scene.materials.push_back(transformed);
  Material plain = transformed;  // the same textures through their own coordinates
  plain.base_color_transform = UvTransform{};
  plain.normal_transform = UvTransform{};
  scene.materials.push_back(plain);
  const GltfMaterialShader shader(scene);

  // Lanes on the floor at assorted uvs and footprints; the same lanes on the plain material at
  // the transformed uvs, footprints widened by the transform's area scale and the position's
  // derivatives along the transformed coordinates must shade alike.
  SurfaceHit<W> hit = floor_hits(0.1f);
  hit.dpdu = vec3<W>(glm::vec3(2.0f, 0.0f, 0.0f));
  hit.dpdv = vec3<W>(glm::vec3(0.0f, 0.0f, 3.0f));
  SurfaceHit<W> expected = hit;
  const glm::mat2 linear(transform.matrix[0], transform.matrix[1]);
  const glm::mat2 inverse = glm::inverse(linear);
  for (int i = 0; i < W; ++i) {
    const glm::vec2 uv(0.13f * float(i) + 0.05f, 0.71f - 0.09f * float(i));
    hit.u.set(i, uv.x);
    hit.v.set(i, uv.y);
    hit.texture_footprint.set(i, i < 4 ? 0.0f : 0.2f * float(i - 3));
    hit.material.set(i, 0);
    const glm::vec2 mapped = transform.apply(uv);
    expected.u.set(i, mapped.x);
    expected.v.set(i, mapped.y);
    expected.texture_footprint.set(i, hit.texture_footprint[i] * std::sqrt(std::abs(glm::determinant(linear))));
    expected.material.set(i, 1);
    expected.dpdu.set(i, hit.dpdu[i] * inverse[0].x + hit.dpdv[i] * inverse[0].y);
    expected.dpdv.set(i, hit.dpdu[i] * inverse[1].x + hit.dpdv[i] * inverse[1].y);
  }
  const vmask<W> all(true);
  const BrdfParameters<W> p = shader.shade(hit, all);
  const BrdfParameters<W> q = shader.shade(expected, all);
  int cut_out = 0;
  for (int i = 0; i < W; ++i) {
    INFO("lane " << i);
    CHECK(glm::length(p.albedo[i] - q.albedo[i]) < 1e-5f);  // float rounding of the transformed coordinates
    CHECK(glm::length(p.normal[i] - q.normal[i]) < 1e-5f);
    CHECK(p.opaque[i] == q.opaque[i]);
    cut_out += p.opaque[i] ? 0 : 1;
  }
  CHECK(cut_out > 0);  // some lanes land on the checker's transparent texel, through the transform
  CHECK(cut_out < W);

  // opaque_at (shadow rays through cut-outs) reads the alpha through the transform too: a
  // candidate on a triangle whose uvs are the lanes' gives the lanes' answer.
  Scene cutout_scene = scene;
  Mesh& triangle = cutout_scene.meshes[0];
  triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
  triangle.uvs = {{0, 0}, {1, 0}, {0, 1}};
  triangle.triangles = {{0, 1, 2}};
  const GltfMaterialShader cutout_shader(cutout_scene);
  for (int i = 0; i < 4; ++i) {  // footprint 0: the alpha at the point, as opaque_at reads it
    const float u = hit.u[i], v = hit.v[i];
    if (u < 0.0f || v < 0.0f || u + v > 1.0f) continue;  // outside the triangle
    OcclusionCandidate candidate{};
    candidate.u = u;
    candidate.v = v;
    candidate.mesh = 0;
    CHECK(cutout_shader.opaque_at(candidate) == p.opaque[i]);
  }
}

TEST_CASE("noise: bounded, zero on the lattice, continuous, seeded and width independent", "[shading][noise]") {
  CHECK(perlin_noise(glm::vec3(3.0f, -2.0f, 7.0f)) == 0.0f);
  double sum = 0.0, sum2 = 0.0;
  float lowest = 0.0f, highest = 0.0f;
  const int n = 4000;
  int differs = 0;
  for (int k = 0; k < n; ++k) {
    const glm::vec3 p(0.37f * float(k), 0.11f * float(k % 97), -0.23f * float(k % 31));
    const float value = perlin_noise(p);
    lowest = std::min(lowest, value);
    highest = std::max(highest, value);
    sum += value;
    sum2 += double(value) * value;
    // Continuity: 1e-3 away the value moves by at most |gradient| (below ~3.5 here) x 1e-3.
    CHECK(std::abs(perlin_noise(p + glm::vec3(1e-3f, 0.0f, 0.0f)) - value) < 4e-3f);
    if (perlin_noise(p, 7) != value) ++differs;
  }
  // Gradients have components in [-1, 1]; trilinear blends of dots with offsets below 1 stay
  // within sqrt(3) in magnitude.
  CHECK(lowest >= -1.7321f);
  CHECK(highest <= 1.7321f);
  CHECK(highest - lowest > 0.5f);  // not constant
  // Zero mean (gradients are symmetric) within a few standard errors.
  const double mean = sum / n, deviation = std::sqrt(sum2 / n - mean * mean);
  CHECK(std::abs(mean) < 4.0 * deviation / std::sqrt(double(n)) + 0.02);
  CHECK(differs > n * 9 / 10);
  // The packet version is the scalar one lane by lane.
  vec3<W> p;
  for (int i = 0; i < W; ++i) p.set(i, {0.3f * float(i) + 0.1f, -1.7f * float(i), 2.9f});
  const vfloat<W> packet = perlin_noise(p, 3);
  for (int i = 0; i < W; ++i) CHECK(packet[i] == perlin_noise(p[i], 3));
  // Non-finite positions give finite noise.
  CHECK(std::isfinite(perlin_noise(glm::vec3(std::numeric_limits<float>::infinity(), 1e30f, -1e30f))));
}

TEST_CASE("procedural shaders: patterns vary, albedo stays in 0..1, bumps tilt normals", "[shading][procedural]") {
  STATIC_REQUIRE(SurfaceShader<MarbleShader, W>);
  STATIC_REQUIRE(SurfaceShader<WoodShader, W>);
  STATIC_REQUIRE(SurfaceShader<BrickBumpShader, W>);
  STATIC_REQUIRE(SurfaceShader<ConstantDiffuseShader, W>);
  const SurfaceHit<W> hit = floor_hits(0.037f);
  vmask<W> mask(true);
  mask.set(7, false);
  const auto check_albedo = [&](const BrdfParameters<W>& p) {
    CHECK(finite(p.albedo));
    float low = 1.0f, high = 0.0f;
    for (int i = 0; i < 7; ++i) {
      const glm::vec3 a = p.albedo[i];
      CHECK(glm::all(glm::greaterThanEqual(a, glm::vec3(0.0f))));
      CHECK(glm::all(glm::lessThanEqual(a, glm::vec3(1.0f))));
      low = std::min(low, a.x);
      high = std::max(high, a.x);
      CHECK(glm::length(p.normal[i]) == Approx(1.0f).epsilon(1e-5));
    }
    CHECK(high - low > 0.02f);  // a pattern, not a constant
    CHECK(p.albedo[7] == glm::vec3(0.0f));
    CHECK(p.opaque == mask);
  };
  check_albedo(MarbleShader{}.shade(hit, mask));
  check_albedo(WoodShader{}.shade(hit, mask));
  check_albedo(BrickBumpShader{}.shade(hit, mask));
  CHECK(ConstantDiffuseShader(glm::vec3(0.3f)).shade(hit, mask).albedo[2] == glm::vec3(0.3f));

  // Bricks: a lane on a joint gets a tilted normal, one in the middle of a brick a flat one;
  // without bump the normal is the shading normal everywhere.
  BrickBumpSettings settings;
  settings.seed = 5;
  SurfaceHit<W> wall = floor_hits(0.0f);
  // Floor (normal +y): bricks in (x, z); rows of 0.08 along z, bricks 0.2 along x.
  wall.position.set(0, {0.1f, 0.0f, 0.04f});                                  // brick centre
  wall.position.set(1, {0.05f, 0.0f, 0.08f + 0.75f * settings.mortar_width});  // on a joint's flank
  wall.position.set(2, {0.05f, 0.0f, 0.08f});                                   // in the joint
  const BrdfParameters<W> bumped = BrickBumpShader(settings).shade(wall, vmask<W>(true));
  CHECK(glm::dot(bumped.normal[0], glm::vec3(0, 1, 0)) > 0.95f);
  CHECK(glm::dot(bumped.normal[1], glm::vec3(0, 1, 0)) < 0.95f);
  CHECK(bumped.albedo[2] == settings.mortar);
  CHECK(glm::length(bumped.albedo[0] - settings.brick) < 0.1f);
  settings.bump = 0.0f;
  const BrdfParameters<W> flat = BrickBumpShader(settings).shade(wall, vmask<W>(true));
  for (int i = 0; i < W; ++i) CHECK(glm::length(flat.normal[i] - glm::vec3(0, 1, 0)) < 1e-6f);
}

TEST_CASE("ScalarShaderAdapter: calls the scalar function on active lanes only", "[shading][adapter]") {
  int calls = 0;
  const auto function = [&calls](const SurfacePoint& point) {
    ++calls;
    ScalarBrdfParameters p;
    p.albedo = glm::vec3(point.position.x, 0.5f, point.uv.x);
    p.normal = point.position.x > 0.15f ? glm::vec3(0.0f, 2.0f, 2.0f) : glm::vec3(0.0f);  // unnormalised / zero
    p.opaque = point.front_face;
    return p;
  };
  const ScalarShaderAdapter adapter(function);
  STATIC_REQUIRE(SurfaceShader<decltype(adapter), W>);
  SurfaceHit<W> hit = floor_hits(0.1f);
  hit.front_face.set(4, false);
  vmask<W> mask(true);
  mask.set(1, false);
  const BrdfParameters<W> p = adapter.shade(hit, mask);
  CHECK(calls == W - 1);
  CHECK(p.albedo[3] == glm::vec3(0.3f, 0.5f, 0.25f) * glm::vec3(1.0f, 1.0f, 1.0f));
  CHECK(p.albedo[1] == glm::vec3(0.0f));
  CHECK(p.normal[0] == glm::vec3(0, 1, 0));  // zero normal -> the hit's shading normal
  CHECK(glm::length(p.normal[3] - glm::normalize(glm::vec3(0, 1, 1))) < 1e-6f);
  CHECK_FALSE(p.opaque[4]);
  CHECK(p.opaque[3]);
}

TEST_CASE("GltfMaterialShader: glTF's specular layer: Fresnel over the view angle, KHR_materials_specular's factors and "
          "textures, Lambertian at specular 0", "[shading][gltf][specular]") {
  // 1 x 1 textures: specular (linear, alpha 128) and specular colour (sRGB codes 255, 188, 64).
  Scene scene = linear_texture_scene(1, 1, {0, 0, 0, 128});
  scene.textures.push_back({.name = "tint", .width = 1, .height = 1, .texels = {255, 188, 64, 255}, .srgb = true});
  const glm::vec4 base{0.6f, 0.5f, 0.4f, 1.0f};
  const Material dielectric{.name = "varnish", .base_color = base, .metallic = 0.0f, .roughness = 0.5f};
  Material rough = dielectric;
  rough.roughness = 1.0f;
  Material matte = dielectric;
  matte.specular = 0.0f;
  Material tinted = dielectric;  // KHR_materials_specular and KHR_materials_ior
  tinted.roughness = 0.05f;      // below the mirror threshold
  tinted.ior = 2.0f;
  tinted.specular = 0.5f;
  tinted.specular_color = {1.0f, 0.5f, 0.25f};
  Material textured = tinted;  // factors 1, the values in the textures
  textured.specular = 1.0f;
  textured.specular_texture = 0;
  textured.specular_color = glm::vec3(1.0f);
  textured.specular_color_texture = 1;
  Material gold{.name = "gold", .base_color = {1.0f, 0.8f, 0.3f, 1.0f}, .metallic = 1.0f, .roughness = 0.5f};
  scene.materials = {dielectric, rough, matte, tinted, textured, gold};
  const GltfMaterialShader shader(scene);

  // Schlick's weight at cosine c, (1 - c)^5, and the view at that cosine to the floor's normal.
  const auto schlick = [](float c) { return std::pow(1.0f - c, 5.0f); };
  const auto view = [](float c) { return glm::vec3(std::sqrt(1.0f - c * c), c, 0.0f); };
  const float cosines[W] = {1.0f, 0.8f, 0.5f, 0.3f, 0.1f, 0.02f, 0.0f, 0.6f};
  const auto shade = [&](int material) {
    SurfaceHit<W> hit = floor_hits(0.1f);
    for (int i = 0; i < W; ++i) {
      hit.material.set(i, material);
      hit.wo.set(i, view(cosines[i]));
    }
    return shader.shade(hit, vmask<W>(true));
  };
  const BrdfParameters<W> varnish = shade(0), rough_varnish = shade(1), paint = shade(2), tint = shade(3),
                          tint_textures = shade(4), metal = shade(5);
  for (int i = 0; i < W; ++i) {
    const float c = cosines[i];
    INFO("cosine " << c);
    // Roughness 0.5: from 4% head-on towards 1 - roughness = 50% at grazing; the diffuse part keeps the rest.
    const float fresnel = gltf_f0 + (0.5f - gltf_f0) * schlick(c);
    CHECK(glm::length(varnish.glossy[i] - glm::vec3(fresnel)) < 1e-6f);
    CHECK(glm::length(varnish.albedo[i] - glm::vec3(base) * (1.0f - fresnel)) < 1e-6f);
    CHECK(varnish.shininess[i] == Approx(30.0f));  // 2 / 0.25^2 - 2, as for metals
    // Roughness 1: 4% at every angle.
    CHECK(glm::length(rough_varnish.glossy[i] - glm::vec3(gltf_f0)) < 1e-6f);
    CHECK(glm::length(rough_varnish.albedo[i] - glm::vec3(base) * dielectric_diffuse) < 1e-6f);
    // Specular 0: exactly Lambertian, the base colour, at every angle.
    CHECK(paint.albedo[i] == glm::vec3(base));
    CHECK(paint.glossy[i] == glm::vec3(0.0f));
    CHECK(paint.mirror[i] == glm::vec3(0.0f));
    // ior 2 (f0 = 1/9) tinted by the colour and halved by the factor; smooth enough to be a mirror,
    // whose Fresnel rises towards the factor (0.5) at grazing; the diffuse part keeps 1 - the largest channel.
    const glm::vec3 f0 = glm::vec3(1.0f, 0.5f, 0.25f) / 9.0f;
    const float undamped = 1.0f - 0.05f;
    const glm::vec3 tint_fresnel = 0.5f * (f0 + (glm::vec3(undamped) - f0) * schlick(c));
    CHECK(glm::length(tint.mirror[i] - tint_fresnel) < 1e-6f);
    CHECK(tint.glossy[i] == glm::vec3(0.0f));
    CHECK(glm::length(tint.albedo[i] - glm::vec3(base) * (1.0f - tint_fresnel.x)) < 1e-6f);
    // The textures' alpha (linear 128 / 255) and colour (sRGB-decoded) scale like factors.
    const float weight = 128.0f / 255.0f;
    const glm::vec3 tint_color(1.0f, srgb_to_linear_table()[188], srgb_to_linear_table()[64]);
    const glm::vec3 texture_f0 = tint_color / 9.0f;
    const glm::vec3 texture_fresnel = weight * (texture_f0 + (glm::vec3(undamped) - texture_f0) * schlick(c));
    CHECK(glm::length(tint_textures.mirror[i] - texture_fresnel) < 1e-6f);
    CHECK(glm::length(tint_textures.albedo[i] - glm::vec3(base) * (1.0f - texture_fresnel.x)) < 1e-6f);
    // Metals: their colour head-on, whiter towards grazing up to 1 - roughness in each channel.
    const glm::vec3 gold_color(1.0f, 0.8f, 0.3f);
    const glm::vec3 gold_fresnel = gold_color + (glm::max(glm::vec3(0.5f), gold_color) - gold_color) * schlick(c);
    CHECK(glm::length(metal.glossy[i] - gold_fresnel) < 1e-6f);
    CHECK(metal.albedo[i] == glm::vec3(0.0f));
    // No lane reflects more than it receives.
    for (const BrdfParameters<W>* p : {&varnish, &rough_varnish, &paint, &tint, &tint_textures, &metal}) {
      const glm::vec3 total = p->albedo[i] + p->glossy[i] + p->mirror[i] + glm::vec3(p->transmission[i]);
      CHECK(glm::all(glm::lessThanEqual(total, glm::vec3(1.0f + 1e-6f))));  // float rounding of a few products
    }
  }
}

TEST_CASE("GltfMaterialShader: no material reflects more than it receives", "[shading][gltf]") {
  // Over a grid of factors, diffuse + glossy + mirror + transmission (which the glass BRDF
  // splits into Fresnel reflection and refraction) stays at most 1 per channel.
  Scene scene;
  Mesh mesh;
  mesh.material = 0;
  scene.meshes.push_back(mesh);
  for (const float metallic : {0.0f, 0.3f, 1.0f})
    for (const float roughness : {0.0f, 0.05f, 0.5f, 1.0f})
      for (const float transmission : {0.0f, 0.5f, 1.0f})
        for (const glm::vec3 color : {glm::vec3(1.0f), glm::vec3(0.9f, 0.2f, 0.5f), glm::vec3(2.0f, -1.0f, 0.5f)})
          scene.materials.push_back({.base_color = glm::vec4(color, 1.0f),
                                     .metallic = metallic,
                                     .roughness = roughness,
                                     .transmission = transmission});
  const GltfMaterialShader shader(scene);
  for (std::size_t m = 0; m < scene.materials.size(); m += W) {
    SurfaceHit<W> hit = floor_hits(0.1f);
    vmask<W> mask;
    for (int i = 0; i < W && m + std::size_t(i) < scene.materials.size(); ++i) {
      hit.material.set(i, int(m) + i);
      mask.set(i, true);
    }
    const BrdfParameters<W> p = shader.shade(hit, mask);
    for (int i = 0; i < W; ++i) {
      if (!mask[i]) continue;
      INFO("material " << m + std::size_t(i));
      const glm::vec3 total = p.albedo[i] + p.glossy[i] + p.mirror[i] + glm::vec3(p.transmission[i]);
      // 1e-6: float rounding of three products.
      CHECK(glm::all(glm::lessThanEqual(total, glm::vec3(1.0f + 1e-6f))));
      CHECK(glm::all(glm::greaterThanEqual(p.albedo[i], glm::vec3(0.0f))));
      CHECK(p.shininess[i] >= 1.0f);
    }
  }
}

namespace {

/// Lane `i` of `hit` as a one-lane packet.
template <int From>
SurfaceHit<1> lane_of(const SurfaceHit<From>& hit, int i) {
  SurfaceHit<1> one;
  one.position.set(0, hit.position[i]);
  one.geometric_normal.set(0, hit.geometric_normal[i]);
  one.shading_normal.set(0, hit.shading_normal[i]);
  one.wo.set(0, hit.wo[i]);
  one.u.set(0, hit.u[i]);
  one.v.set(0, hit.v[i]);
  one.dpdu.set(0, hit.dpdu[i]);
  one.dpdv.set(0, hit.dpdv[i]);
  one.texture_footprint.set(0, hit.texture_footprint[i]);
  one.distance.set(0, hit.distance[i]);
  one.material.set(0, hit.material[i]);
  one.mesh.set(0, hit.mesh[i]);
  one.instance.set(0, hit.instance[i]);
  one.triangle.set(0, hit.triangle[i]);
  one.front_face.set(0, hit.front_face[i]);
  return one;
}

/// A `size` x `size` texture of pseudo-random texels.
Texture noise_texture(int size, bool srgb, std::mt19937& random) {
  Texture t{.name = "noise", .width = size, .height = size, .srgb = srgb};
  t.texels.resize(std::size_t(size) * std::size_t(size) * 4);
  for (std::uint8_t& c : t.texels) c = std::uint8_t(random() % 256);
  return t;
}

}  // namespace

TEST_CASE("GltfMaterialShader: a packet's lanes shade as each does alone, whatever the materials, levels and masks",
          "[shading][gltf]") {
  // The shader runs one material's lanes together, each lane reading its own mip levels: every
  // lane of a 16-lane packet mixing materials, footprints, faces and inactive lanes must equal
  // the same hit shaded in a packet of one (to float rounding: the compiler may fuse a multiply
  // and an add in one width and not the other).
  std::mt19937 random(7);
  Scene scene;
  scene.textures.push_back(noise_texture(64, true, random));   // 0: base colour with alpha
  scene.textures.push_back(noise_texture(16, false, random));  // 1: metallic-roughness
  scene.textures.push_back(noise_texture(32, false, random));  // 2: normals
  scene.textures.push_back(noise_texture(8, false, random));   // 3: specular (alpha)
  scene.textures.push_back(noise_texture(128, true, random));  // 4: emission, specular colour
  for (int m = 0; m < 3; ++m) {
    Mesh mesh;
    mesh.material = m == 2 ? -1 : m;  // mesh 2 has the default material
    scene.meshes.push_back(mesh);
  }
  const UvTransform turned = UvTransform::from({0.3f, -0.2f}, 0.4f, {1.5f, 0.75f});
  Material cutout{.name = "cutout", .base_color = {0.9f, 0.8f, 0.7f, 1.0f}, .base_color_texture = 0, .metallic = 0.0f};
  cutout.alpha_mode = AlphaMode::mask;
  cutout.base_color_transform = turned;
  Material metal{.name = "metal", .base_color = {1.0f, 0.7f, 0.4f, 1.0f}, .metallic = 1.0f, .roughness = 0.8f};
  metal.metallic_roughness_texture = 1;
  metal.normal_texture = 2;
  metal.normal_transform = turned;
  Material varnish{.name = "varnish", .base_color_texture = 0, .metallic = 0.0f, .roughness = 0.3f};
  varnish.specular_texture = 3;
  varnish.specular_color_texture = 4;
  varnish.normal_texture = 2;
  varnish.normal_scale = 0.5f;
  Material lamp{.name = "lamp", .base_color = {1, 1, 1, 1}, .metallic = 0.0f, .emission = {2, 3, 4}};
  lamp.emissive_texture = 4;
  lamp.emissive_transform = turned;
  Material shiny{.name = "shiny", .base_color = {0.5f, 0.5f, 0.5f, 1.0f}, .metallic = 0.5f, .roughness = 0.05f};
  shiny.metallic_roughness_texture = 1;
  for (const Material& m : {cutout, metal, varnish, lamp, shiny}) scene.materials.push_back(m);
  const GltfMaterialShader shader(scene);

  constexpr int Wide = 16;
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const auto direction = [&] {
    const float z = 2.0f * unit(random) - 1.0f, phi = 6.2831853f * unit(random), r = std::sqrt(1.0f - z * z);
    return glm::vec3(r * std::cos(phi), r * std::sin(phi), z);
  };
  const float nan = std::numeric_limits<float>::quiet_NaN(), infinity = std::numeric_limits<float>::infinity();
  int compared = 0, minified = 0;
  for (int round = 0; round < 200; ++round) {
    SurfaceHit<Wide> hit;
    vmask<Wide> mask;
    // Half the packets on one material, as most of a frame's are; the rest mixed.
    const int shared_material = round % 2 == 0 ? int(random() % 6) - 1 : -2;
    for (int i = 0; i < Wide; ++i) {
      const glm::vec3 normal = direction();
      glm::vec3 wo = direction();
      if (glm::dot(wo, normal) < 0.0f) wo = -wo;
      hit.geometric_normal.set(i, normal);
      hit.shading_normal.set(i, normal);
      hit.wo.set(i, wo);
      const int kind = int(random() % 16);
      hit.u.set(i, kind == 0 ? nan : kind == 1 ? infinity : 6.0f * unit(random) - 3.0f);
      hit.v.set(i, kind == 2 ? -infinity : 6.0f * unit(random) - 3.0f);
      hit.dpdu.set(i, kind == 3 ? glm::vec3(0.0f) : direction() * (0.1f + unit(random)));
      hit.dpdv.set(i, direction() * (0.1f + unit(random)));
      // Footprints from well below a texel to wider than the largest texture, and the odd ones.
      const float footprint = std::exp2(-12.0f + 14.0f * unit(random));
      hit.texture_footprint.set(i, kind == 4 ? 0.0f : kind == 5 ? nan : kind == 6 ? infinity : footprint);
      const int material = shared_material != -2 ? shared_material : int(random() % 6) - 1;
      hit.material.set(i, material);
      hit.mesh.set(i, material == -1 ? 2 : int(random() % 2));
      hit.front_face.set(i, random() % 4 != 0);
      mask.set(i, random() % 8 != 0);
    }
    const BrdfParameters<Wide> packet = shader.shade(hit, mask);
    for (int i = 0; i < Wide; ++i) {
      INFO("round " << round << ", lane " << i << ", material " << hit.material[i] << ", footprint " << hit.texture_footprint[i]);
      if (!mask[i]) {
        CHECK(packet.albedo[i] == glm::vec3(0.0f));
        CHECK(packet.normal[i] == glm::vec3(0.0f));
        CHECK(packet.emission[i] == glm::vec3(0.0f));
        CHECK_FALSE(packet.opaque[i]);
        continue;
      }
      const BrdfParameters<1> alone = shader.shade(lane_of(hit, i), vmask<1>(true));
      // 1e-5: a few float roundings of values up to 4 (the lamp's emission), where one fused
      // multiply-add more or less changes the last bits.
      const auto near = [](const glm::vec3& a, const glm::vec3& b) { return glm::length(a - b) <= 1e-5f * (1.0f + glm::length(b)); };
      CHECK(near(packet.albedo[i], alone.albedo[0]));
      CHECK(near(packet.glossy[i], alone.glossy[0]));
      CHECK(near(packet.mirror[i], alone.mirror[0]));
      CHECK(near(packet.normal[i], alone.normal[0]));
      CHECK(near(packet.emission[i], alone.emission[0]));
      CHECK(packet.shininess[i] == Approx(alone.shininess[0]).epsilon(1e-5));
      CHECK(packet.transmission[i] == alone.transmission[0]);
      CHECK(packet.ior[i] == alone.ior[0]);
      CHECK(packet.opaque[i] == alone.opaque[0]);
      CHECK(std::abs(glm::length(packet.normal[i]) - 1.0f) < 1e-5f);
      ++compared;
      minified += std::isfinite(hit.texture_footprint[i]) && hit.texture_footprint[i] > 1.0f / 32.0f ? 1 : 0;
    }
  }
  CHECK(compared > 2000);
  CHECK(minified > 500);
}

TEST_CASE("GltfMaterialShader: KHR_materials_clearcoat reflects Schlick's 4% over the view angle, as a mirror or in the "
          "glossy lobe, and dims all below it",
          "[shading][gltf][clearcoat]") {
  // A coat texture of red 128 (the coat's weight x 128/255) and green 64 (its roughness x 64/255).
  Scene scene = linear_texture_scene(1, 1, {128, 64, 0, 255});
  Material base{.name = "base", .base_color = {0.5f, 0.4f, 0.3f, 1.0f}, .metallic = 0.0f, .emission = {1, 2, 3}};
  base.specular = 0.0f;  // a Lambertian base: everything glossy or mirror below is the coat's
  Material smooth = base;
  smooth.name = "smooth";
  smooth.clearcoat = 1.0f;
  Material rough = smooth;
  rough.name = "rough";
  rough.clearcoat_roughness = 0.5f;
  Material textured = rough;
  textured.name = "textured";
  textured.clearcoat_texture = 0;
  textured.clearcoat_roughness_texture = 0;
  Material rough_metal = rough;  // a metal's own lobe reflects more than the coat: its exponent stays
  rough_metal.name = "rough metal";
  rough_metal.metallic = 1.0f;
  for (const Material& m : {base, smooth, rough, textured, rough_metal}) scene.materials.push_back(m);
  const GltfMaterialShader shader(scene);

  for (const float cosine : {1.0f, 0.8f, 0.5f, 0.2f, 0.05f}) {
    SurfaceHit<W> hit = floor_hits(0.1f);
    const glm::vec3 wo(std::sqrt(1.0f - cosine * cosine), cosine, 0.0f);
    hit.wo = vec3<W>(wo);
    for (int i = 0; i < 5; ++i) hit.material.set(i, i);
    const vmask<W> mask = vmask<W>::first(5);
    const BrdfParameters<W> p = shader.shade(hit, mask);
    INFO("cosine " << cosine);
    const float x = 1.0f - cosine, x5 = x * x * x * x * x;
    // Schlick from f0 = 4%, its rise to 1 - roughness (rough_fresnel).
    const auto fresnel = [&](float weight, float roughness) {
      return weight * (0.04f + (std::max(1.0f - roughness, 0.04f) - 0.04f) * x5);
    };
    const auto near = [](const glm::vec3& a, const glm::vec3& b) { return glm::length(a - b) < 1e-6f; };
    // No coat: Lambertian, no reflection.
    CHECK(p.mirror[0] == glm::vec3(0.0f));
    CHECK(p.glossy[0] == glm::vec3(0.0f));
    const glm::vec3 albedo = p.albedo[0], emission = p.emission[0];
    // A smooth coat is a mirror of F; the base keeps 1 - F of its diffuse and emitted light.
    const float smooth_f = fresnel(1.0f, 0.0f);
    CHECK(near(p.mirror[1], glm::vec3(smooth_f)));
    CHECK(p.glossy[1] == glm::vec3(0.0f));
    CHECK(near(p.albedo[1], albedo * (1.0f - smooth_f)));
    CHECK(near(p.emission[1], emission * (1.0f - smooth_f)));
    // A rough coat joins the glossy lobe with its exponent, 2 / 0.5^4 - 2 = 30.
    const float rough_f = fresnel(1.0f, 0.5f);
    CHECK(near(p.glossy[2], glm::vec3(rough_f)));
    CHECK(p.mirror[2] == glm::vec3(0.0f));
    CHECK(p.shininess[2] == Approx(30.0f));
    CHECK(near(p.albedo[2], albedo * (1.0f - rough_f)));
    // The textures scale the factors: weight 128/255, roughness 0.5 x 64/255 (0.125, still above
    // the mirror roughness 0.1).
    const float textured_f = fresnel(128.0f / 255.0f, 0.5f * 64.0f / 255.0f);
    CHECK(near(p.glossy[3], glm::vec3(textured_f)));
    CHECK(p.shininess[3] == Approx(2.0f / std::pow(0.5f * 64.0f / 255.0f, 4.0f) - 2.0f).epsilon(1e-4));
    CHECK(near(p.albedo[3], albedo * (1.0f - textured_f)));
    // Over a rough metal (roughness 1, exponent 1, reflecting its base colour) the one lobe holds
    // both reflections, with the exponent of the one that reflects more: the metal's, but the
    // coat's at grazing angles.
    const float metal = 0.5f * (1.0f - rough_f);
    CHECK(p.shininess[4] == Approx(rough_f > metal ? 30.0f : 1.0f));
    CHECK(p.albedo[4] == glm::vec3(0.0f));
    CHECK(near(p.glossy[4], glm::vec3(0.5f, 0.4f, 0.3f) * (1.0f - rough_f) + glm::vec3(rough_f)));
    // Nothing reflects more than it receives.
    for (int i = 0; i < 5; ++i) {
      const glm::vec3 total = p.albedo[i] + p.glossy[i] + p.mirror[i] + glm::vec3(p.transmission[i]);
      CHECK(glm::all(glm::lessThanEqual(total, glm::vec3(1.0f + 1e-6f))));  // float rounding
    }
  }
}
