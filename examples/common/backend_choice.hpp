#pragma once
// From a backend named on the command line to a backend type: every Renderer (and path tracer)
// over a backend is a template instantiation of its own, so a program names the backend types it
// is built with in a BackendList, and a name plus a packet width picks one of them at run time.
// Only the listed types are instantiated: a program that lists fewer compiles faster.

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>

#include "common/command_line.hpp"

namespace igi::programs {

/// The backend types a program can run, in the order it lists them (igi-view's B key cycles through it).
template <class... Backends>
struct BackendList {
  /// How many backend types the list holds.
  static constexpr std::size_t size = sizeof...(Backends);
};

/// A backend type's name and packet width, as the command line names it.
struct BackendChoice {
  const char* backend;  ///< "embree", "reference" or "saarcor" (the type's name()).
  int packet;           ///< Packet width W (the type's width).
};

/// The name and width of every type of `list`, in its order.
template <class... Backends>
constexpr std::array<BackendChoice, sizeof...(Backends)> backend_choices(BackendList<Backends...> /*list*/) {
  return {BackendChoice{Backends::name(), Backends::width}...};
}

/// The choices of `list` as "embree/1,4,8,16, reference/8, saarcor/64": widths of neighbouring
/// types of one name are joined after one name.
template <class... Backends>
std::string describe_backends(BackendList<Backends...> list) {
  std::string text;
  std::string_view previous;
  for (const BackendChoice& choice : backend_choices(list)) {
    // Appended piece by piece: "," + std::to_string(...) inserts at the front of a temporary,
    // which GCC 12 flags (-Wrestrict, a false positive) where it inlines this function.
    if (choice.backend == previous) {
      text += ',';
      text += std::to_string(choice.packet);
      continue;
    }
    if (!text.empty()) text += ", ";
    text += choice.backend;
    text += '/';
    text += std::to_string(choice.packet);
    previous = choice.backend;
  }
  return text;
}

/// Calls `run.template operator()<B>()` for each type B of `list`, in its order.
template <class... Backends, class Run>
void for_each_backend(BackendList<Backends...> /*list*/, Run&& run) {
  (run.template operator()<Backends>(), ...);
}

/// Returns `run.template operator()<B>()` with the type B of `list` whose name() is `backend` and
/// whose width is `packet`; throws UsageError naming the choices when `list` has no such type.
template <class... Backends, class Run>
auto with_backend_of(BackendList<Backends...> list, std::string_view backend, int packet, Run&& run) {
  static_assert(sizeof...(Backends) > 0, "a program runs at least one backend type");
  using Result = decltype(run.template operator()<std::tuple_element_t<0, std::tuple<Backends...>>>());
  std::optional<Result> result;
  const auto run_if_chosen = [&]<class B>() {
    if (backend != B::name() || packet != B::width) return false;
    result.emplace(run.template operator()<B>());
    return true;
  };
  if (!(run_if_chosen.template operator()<Backends>() || ...))
    throw UsageError("--backend/--packet: " + std::string(backend) + "/" + std::to_string(packet) + " is not one of " +
                     describe_backends(list));
  return Result(std::move(*result));
}

}  // namespace igi::programs
