#pragma once
// A one-line progress bar on stderr for long runs of the programs (frames of an animation, passes
// of the path tracer). It draws only when stderr is a terminal, so pipes, files and CI logs never
// see it; the text itself comes from progress_line, a pure function the tests check.

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>

namespace igi::programs {

/// The bar's text: "[=========>          ] 12/40 frames  30%  eta 3.2 s". `done` is clamped to
/// `total`; the estimate is left out until something is done (no rate yet) and once all is done.
inline std::string progress_line(std::uint64_t done, std::uint64_t total, double elapsed_seconds, int bar_width,
                                 const std::string& unit) {
  done = std::min(done, total);
  const double fraction = total > 0 ? double(done) / double(total) : 1.0;
  const int filled = int(fraction * bar_width);
  std::string bar(std::size_t(std::max(bar_width, 0)), ' ');
  for (int i = 0; i < filled; ++i) bar[std::size_t(i)] = '=';
  if (filled < bar_width) bar[std::size_t(filled)] = '>';
  std::string line = "[" + bar + "] " + std::to_string(done) + "/" + std::to_string(total) + " " + unit;
  char tail[64];
  std::snprintf(tail, sizeof tail, " %3d%%", int(fraction * 100.0));
  line += tail;
  if (done > 0 && done < total) {
    std::snprintf(tail, sizeof tail, "  eta %.1f s", elapsed_seconds * double(total - done) / double(done));
    line += tail;
  }
  return line;
}

/// True if `stream` is a terminal (the bar is meant for people, not for logs).
inline bool is_terminal(std::FILE* stream) { return ::isatty(::fileno(stream)) == 1; }

/// Progress of `total` units of work, drawn on stderr when it is a terminal and there is more
/// than one unit; erased again when done, so only the program's own messages remain.
class ProgressBar {
 public:
  /// Characters between the brackets: the whole line stays under 80 columns.
  static constexpr int bar_width = 40;
  /// Redraws at most this often: a terminal keeps up, and fast loops do not spend time printing.
  static constexpr double redraw_seconds = 0.1;

  /// A bar over `total` units named `unit` ("frames", "spp"); drawn if `enabled` (default: stderr
  /// is a terminal) and total > 1.
  ProgressBar(std::uint64_t total, std::string unit, bool enabled = is_terminal(stderr))
      : total_(total), unit_(std::move(unit)), enabled_(enabled && total > 1), start_(clock::now()) {
    draw();
  }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  /// Erases the bar.
  ~ProgressBar() { finish(); }

  /// Marks `units` more as done and redraws if enough time has passed (always on the last one).
  void advance(std::uint64_t units = 1) {
    done_ += units;
    if (!enabled_) return;
    if (done_ >= total_ || seconds_since(last_draw_) >= redraw_seconds) draw();
  }

  /// Erases the bar (idempotent), leaving the cursor at the start of an empty line.
  void finish() {
    if (!enabled_) return;
    std::fputs("\r\033[K", stderr);  // carriage return, then ANSI "erase to end of line"
    std::fflush(stderr);
    enabled_ = false;
  }

 private:
  using clock = std::chrono::steady_clock;
  double seconds_since(clock::time_point t) const { return std::chrono::duration<double>(clock::now() - t).count(); }
  void draw() {
    if (!enabled_) return;
    last_draw_ = clock::now();
    const std::string line = progress_line(done_, total_, seconds_since(start_), bar_width, unit_);
    std::fprintf(stderr, "\r%s\033[K", line.c_str());
    std::fflush(stderr);
  }

  std::uint64_t total_;
  std::uint64_t done_ = 0;
  std::string unit_;
  bool enabled_;
  clock::time_point start_;
  clock::time_point last_draw_;
};

}  // namespace igi::programs
