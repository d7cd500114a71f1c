#pragma once
// SIGINT and SIGTERM as a stop request for igi's programs. A renderer embedded in a terminal
// session, a script or a cluster job must end when asked, even in the middle of a long frame, and
// must not leave a half-written image behind (images are written to a temporary file and renamed,
// igi/io/image.hpp, so an image on disk is always whole).

#include <chrono>

namespace igi::programs {

/// How long a program has, after the first SIGINT or SIGTERM, to stop by itself before the
/// process ends anyway: 800 ms, so that it is gone within a second, whatever it was doing.
inline constexpr std::chrono::milliseconds stop_grace{800};

/// Makes SIGINT and SIGTERM a stop request. Call it first in main, before any thread starts:
/// threads inherit the blocked signals and one watcher thread takes them. After a signal,
/// `stop_requested()` is true; the program stops between frames, writes nothing more and returns
/// `stop_exit_code()`. If it is still running `grace` later, or a second signal arrives, the
/// watcher ends the process with that exit code.
void install_stop_signals(std::chrono::milliseconds grace = stop_grace);

/// True once SIGINT or SIGTERM has arrived.
bool stop_requested() noexcept;

/// 128 + the signal's number (130 for SIGINT, 143 for SIGTERM), as a shell reports a program a
/// signal ended; 0 before any signal.
int stop_exit_code() noexcept;

/// Prints "program: stopped by signal N; nothing more written" to stderr and returns
/// stop_exit_code(), for `if (stop_requested()) return stopped("igi-render");`.
int stopped(const char* program);

}  // namespace igi::programs
