#pragma once
/// \file
/// A memory budget for allocations whose size comes from input (a glTF accessor's count, an
/// image's dimensions, a frame's resolution): they are checked against it first, so input that
/// would not fit fails with a clear message instead of std::bad_alloc or the OOM killer.

#include <unistd.h>

#include <atomic>
#include <cstddef>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

namespace igi {

namespace detail {
/// The cap set_memory_budget installed; 0 means none.
inline std::atomic<std::size_t> memory_budget_cap{0};
}  // namespace detail

/// Memory the system can still give this process: MemAvailable of /proc/meminfo (free memory plus
/// reclaimable caches), else the free physical pages; SIZE_MAX when neither can be read.
inline std::size_t available_memory() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  std::size_t kibibytes = 0;
  std::string unit;
  while (meminfo >> key >> kibibytes >> unit)
    if (key == "MemAvailable:") return kibibytes * 1024;
  const long pages = ::sysconf(_SC_AVPHYS_PAGES);
  const long page_size = ::sysconf(_SC_PAGESIZE);
  if (pages > 0 && page_size > 0) return std::size_t(pages) * std::size_t(page_size);
  return std::numeric_limits<std::size_t>::max();
}

/// Caps the budget at `bytes` for the whole process (0 removes the cap): for embedders that
/// share the machine, and for fuzzers whose own memory limit is lower than the machine's.
inline void set_memory_budget(std::size_t bytes) noexcept { detail::memory_budget_cap.store(bytes); }

/// Bytes one input-sized allocation may take: the available memory, or the cap if lower.
inline std::size_t memory_budget() {
  const std::size_t cap = detail::memory_budget_cap.load();
  const std::size_t available = available_memory();
  return cap != 0 && cap < available ? cap : available;
}

/// `bytes` as "1.5 GiB" (or "12 MiB", "512 bytes") for messages.
inline std::string memory_text(double bytes) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int unit = 0;
  while (bytes >= 1024.0 && unit < 6) {
    bytes /= 1024.0;
    ++unit;
  }
  std::ostringstream out;
  out.precision(unit == 0 ? 0 : 3);
  out << (unit == 0 ? std::fixed : std::defaultfloat) << bytes << ' ' << units[unit];
  return out.str();
}

/// Empty if `count` items of `item_bytes` each fit in the budget, else "needs N GiB, more than the M GiB of memory available".
inline std::string memory_shortfall(double count, double item_bytes) {
  // double: count x size may overflow size_t for absurd counts (2^40 triangles x 36 bytes does not, 2^62 does).
  const double bytes = count * item_bytes;
  const double budget = double(memory_budget());
  if (bytes <= budget) return {};
  return "needs " + memory_text(bytes) + ", more than the " + memory_text(budget) + " of memory available";
}

}  // namespace igi
