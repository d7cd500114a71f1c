#pragma once
/// \file
/// A filter chosen at run time among the filter policies, for programs that let the user
/// pick one without instantiating the pipeline once per filter. The choice costs one switch per tile.

#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>

#include "igi/filters/atrous_filter.hpp"
#include "igi/filters/tile_filters.hpp"

namespace igi {

/// One of DiscontinuityFilter, AtrousFilter, BoxFilter or NoFilter (each with default settings),
/// itself a StagedFilter, so one process's tiles share AtrousFilter's stages as they would with it alone.
class FilterChoice {
 public:
  /// Policy name.
  static constexpr const char* name() noexcept { return "choice"; }

  /// The filter called `filter_name` ("discontinuity", "atrous", "box" or "none"); throws std::invalid_argument otherwise.
  explicit FilterChoice(std::string_view filter_name) {
    if (filter_name == DiscontinuityFilter::name())
      filter_ = DiscontinuityFilter{DiscontinuityFilter::Settings{}};
    else if (filter_name == AtrousFilter::name())
      filter_ = AtrousFilter{AtrousFilter::Settings{}};
    else if (filter_name == BoxFilter::name())
      filter_ = BoxFilter{};
    else if (filter_name == NoFilter::name())
      filter_ = NoFilter{};
    else
      throw std::invalid_argument("unknown filter '" + std::string(filter_name) + "' (discontinuity, atrous, box or none)");
  }

  /// Name of the chosen filter.
  const char* chosen() const noexcept {
    return std::visit([](const auto& f) { return f.name(); }, filter_);
  }

  /// Border the chosen filter reads around a tile.
  int border(int interleave) const noexcept {
    return std::visit([&](const auto& f) { return f.border(interleave); }, filter_);
  }

  /// Runs the chosen filter.
  void apply(const TileGBuffer& gbuffer, int interleave, FilteredTile& out) const {
    std::visit([&](const auto& f) { f.apply(gbuffer, interleave, out); }, filter_);
  }

  /// What a tile keeps between stages: the chosen StagedFilter's, or for a filter that runs whole
  /// (one stage, applied by `finish`) the interleave it was given.
  struct TileStages {
    AtrousFilter::TileStages atrous;  ///< AtrousFilter's stages.
    int interleave = 1;               ///< S, for a filter that runs whole.
  };
  /// The chosen filter's stages (StagedFilter); 1 for a filter that runs whole.
  int stage_count() const noexcept {
    return staged_or_whole([](const auto& f) { return f.stage_count(); }, [](const auto&) { return 1; });
  }
  /// Pixels of stage `stage - 1` that stage `stage` reads around a tile (StagedFilter).
  int stage_reach(int stage) const noexcept {
    return staged_or_whole([&](const auto& f) { return f.stage_reach(stage); }, [](const auto&) { return 0; });
  }
  /// Border of a tile whose tiles share theirs (StagedFilter): the chosen StagedFilter's, or all
  /// of `border` for a filter that runs whole in `finish`.
  int staged_border(int interleave) const noexcept {
    return staged_or_whole([&](const auto& f) { return f.staged_border(interleave); },
                           [&](const auto& f) { return f.border(interleave); });
  }
  /// Stage `stage` of the chosen filter (StagedFilter); a filter that runs whole only notes `interleave`.
  void run_stage(int stage, const TileGBuffer& gbuffer, int interleave, TileStages& tile) const {
    tile.interleave = interleave;
    staged_or_whole([&](const auto& f) { f.run_stage(stage, gbuffer, interleave, stages(tile, f)); }, [](const auto&) {});
  }
  /// Copies `block` of a neighbour's stage `stage` output into `tile`'s (StagedFilter).
  void copy_stage(int stage, const TileStages& neighbour, const BlockCopy& block, TileStages& tile) const {
    staged_or_whole([&](const auto& f) { f.copy_stage(stage, stages(neighbour, f), block, stages(tile, f)); },
                    [](const auto&) {});
  }
  /// The chosen filter's result for the interior of `gbuffer` (StagedFilter): its last stage's, or the whole filter applied.
  void finish(const TileGBuffer& gbuffer, const TileStages& tile, FilteredTile& out) const {
    staged_or_whole([&](const auto& f) { f.finish(gbuffer, stages(tile, f), out); },
                    [&](const auto& f) { f.apply(gbuffer, tile.interleave, out); });
  }

 private:
  /// `staged(f)` of the chosen filter f if it is a StagedFilter, else `whole(f)` (the return type
  /// is spelled out: deduced, it could not be used by the members above).
  template <class Staged, class Whole>
  std::invoke_result_t<Whole&, const NoFilter&> staged_or_whole(Staged&& staged, Whole&& whole) const {
    return std::visit(
        [&](const auto& f) {
          if constexpr (StagedFilter<std::decay_t<decltype(f)>>)
            return staged(f);
          else
            return whole(f);
        },
        filter_);
  }
  /// `tile`'s stages of AtrousFilter `filter` (the only StagedFilter among the choices).
  template <class Tile>
  static auto& stages(Tile& tile, const AtrousFilter&) noexcept {
    return tile.atrous;
  }

  std::variant<DiscontinuityFilter, AtrousFilter, BoxFilter, NoFilter> filter_{NoFilter{}};
};

}  // namespace igi
