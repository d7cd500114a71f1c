#pragma once
/// \file
/// A filter chosen at run time among the filter policies, for programs that let the user
/// pick one without instantiating the pipeline once per filter. The choice costs one switch per tile.

#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>

#include "igi/filters/atrous_filter.hpp"
#include "igi/filters/tile_filters.hpp"

namespace igi {

/// One of DiscontinuityFilter, AtrousFilter, BoxFilter or NoFilter (each with default settings), itself a Filter.
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

 private:
  std::variant<DiscontinuityFilter, AtrousFilter, BoxFilter, NoFilter> filter_{NoFilter{}};
};

}  // namespace igi
