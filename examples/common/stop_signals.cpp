#include "common/stop_signals.hpp"

#include <pthread.h>
#include <signal.h>
#include <time.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>

namespace igi::programs {
namespace {

std::atomic<int> received{0};  ///< The first stop signal's number, 0 before one.

/// The signals that ask a program to stop.
sigset_t stop_set() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}

/// The watcher: waits for a stop signal, records it, then gives the program `grace` to return.
void watch(std::chrono::milliseconds grace) {
  const sigset_t set = stop_set();
  int signal = 0;
  while (sigwait(&set, &signal) != 0) {
  }
  received.store(signal);
  const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(grace);
  timespec remaining{time_t(seconds.count()), long(std::chrono::nanoseconds(grace - seconds).count())};
  // A second signal ends the process at once; a wait interrupted otherwise (EINTR, which
  // nothing here causes) starts again.
  for (;;) {
    const int second = sigtimedwait(&set, nullptr, &remaining);
    if (second > 0 || errno == EAGAIN) break;
  }
  std::fprintf(stderr, "stopped by signal %d after %lld ms of grace\n", signal, (long long)grace.count());
  std::_Exit(128 + signal);
}

}  // namespace

void install_stop_signals(std::chrono::milliseconds grace) {
  const sigset_t set = stop_set();
  if (const int error = pthread_sigmask(SIG_BLOCK, &set, nullptr); error != 0)
    throw std::runtime_error("cannot block SIGINT and SIGTERM (error " + std::to_string(error) + ")");
  std::thread(watch, grace).detach();
}

bool stop_requested() noexcept { return received.load(std::memory_order_relaxed) != 0; }

int stop_exit_code() noexcept {
  const int signal = received.load();
  return signal != 0 ? 128 + signal : 0;
}

int stopped(const char* program) {
  std::fprintf(stderr, "%s: stopped by signal %d; nothing more written\n", program, received.load());
  return stop_exit_code();
}

}  // namespace igi::programs
