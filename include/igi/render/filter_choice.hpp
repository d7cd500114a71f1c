#pragma once
/// \file
/// A filter chosen at run time among the three filter policies, for programs that let the user
/// pick one without instantiating the pipeline three times. The choice costs one switch per tile.

#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>

#include "igi/filters/tile_filters.hpp"

namespace igi {

/// One of DiscontinuityFilter, BoxFilter or NoFilter, itself a Filter.
class FilterChoice {
 public:
  /// Policy name.
  static constexpr const char* name() noexcept { return "choice"; }

  /// The filter called `filter_name` ("discontinuity", "box" or "none"); throws std::invalid_argument otherwise.
  explicit FilterChoice(std::string_view filter_name) {
    if (filter_name == DiscontinuityFilter::name())
      filter_ = DiscontinuityFilter{DiscontinuityFilter::Settings{}};
    else if (filter_name == BoxFilter::name())
      filter_ = BoxFilter{};
    else if (filter_name == NoFilter::name())
      filter_ = NoFilter{};
    else
      throw std::invalid_argument("unknown filter '" + std::string(filter_name) + "' (discontinuity, box or none)");
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
  std::variant<DiscontinuityFilter, BoxFilter, NoFilter> filter_{NoFilter{}};
};

}  // namespace igi
