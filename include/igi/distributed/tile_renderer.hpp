#pragma once
/// \file
/// One rank's renderer in the tile farm: applies broadcast scene changes, builds the frame's VPLs
/// itself from the frame index (VPL sets never cross the network) and renders, filters and tone
/// maps the tiles it is handed. The TileEngine under it is the one under Renderer, so a tile is
/// the same here as in a single-process frame.

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "igi/distributed/messages.hpp"
#include "igi/render/tile_engine.hpp"

namespace igi {

/// Renders single tiles of frames of a scene for the tile farm: a front end on the TileEngine that
/// keeps the camera of the last broadcast changes. The scene and policies are borrowed.
template <class B, class Surface, class Brdf, class Sampler, class F>
class TileRenderer {
 public:
  /// The engine that renders the tiles.
  using Engine = TileEngine<B, Surface, Brdf, Sampler, F>;

  /// Builds the backend for `scene`; throws SettingsError for unusable settings and
  /// std::invalid_argument for a scene without triangles.
  TileRenderer(Scene& scene, const RenderSettings& settings, const Surface& surface, const Brdf& brdf,
               const Sampler& sampler, const F& filter)
      : engine_(scene, settings, surface, brdf, sampler, filter) {}

  /// Applies broadcast scene changes (they take effect at the next begin_frame); throws SceneError on bad indices.
  void apply(const SceneChanges& changes) {
    engine_.apply(changes);
    camera_ = changes.camera;
  }

  /// Prepares frame `index` with the camera of the last apply(): commits scene changes, generates
  /// the frame's VPLs and sets up the shared frame state with `tone_mapping`.
  void begin_frame(std::uint32_t index, const ToneMapping& tone_mapping) {
    engine_.begin_frame(camera_, index, tone_mapping);
  }

  /// Renders tile `tile` of the current frame into `out` (any thread; each has its own workspace).
  /// Throws DistributedError for a tile outside the frame or a call before begin_frame.
  void render(int tile, TileResult& out) {
    if (tile < 0 || std::size_t(tile) >= engine_.tiles().size())
      throw DistributedError("tile " + std::to_string(tile) + " is outside 0.." + std::to_string(engine_.tiles().size() - 1));
    if (!engine_.frame().prepared()) throw DistributedError("TileRenderer::render called before begin_frame");
    engine_.render_tile(tile, out);
  }

  /// Renders the given tiles in parallel on this renderer's threads (one tile per task, demand
  /// driven) into `results[i]`; `after(i, result, milliseconds)` runs on the rendering thread after tile `tiles[i]`.
  template <class After>
  void render_all(std::span<const int> tiles, std::vector<TileResult>& results, After&& after) {
    results.resize(tiles.size());
    engine_.render_tiles(tiles, [&](std::size_t i, TileResult& result, double milliseconds) {
      std::swap(results[i], result);  // the thread's buffer takes results[i]'s old one for its next tile
      after(i, results[i], milliseconds);
    });
  }

  /// The frame's tiles, in make_tiles order.
  const std::vector<PixelRect>& tiles() const noexcept { return engine_.tiles(); }
  /// The settings.
  const RenderSettings& settings() const noexcept { return engine_.settings(); }
  /// The scene as of the last apply().
  const Scene& scene() const noexcept { return engine_.scene(); }
  /// VPLs in all sets of the current frame.
  int vpl_count() const noexcept { return engine_.frame().vpl_count(); }

 private:
  Engine engine_;
  Camera camera_;
};

}  // namespace igi
