// igi-render, igi-view and igi-cluster end within a second of SIGINT or SIGTERM, between frames
// or in the middle of a long one, with the exit status a shell expects (128 + signal) and no
// image, whole or partial, left behind (examples/common/stop_signals.hpp).

#include <catch2/catch.hpp>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

/// A fresh scratch folder for one test.
fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("igi_signal_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// The files in `dir`, hidden temporaries included.
std::vector<std::string> files_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  return names;
}

/// The program is running and busy when the signal comes: 1.5 s after the start it has loaded the
/// Cornell box and is rendering (well under a second on an idle machine, even with sanitizers).
constexpr auto busy = 1500ms;

/// The limit the programs promise, plus the 5 ms poll of ChildProcess::wait_for and process
/// teardown (unmapping a few hundred MB takes tens of ms; 200 ms leaves room on a loaded machine).
constexpr auto promised = 1000ms + 200ms;

/// Sends `signal` to `child` once it is busy and checks it ends in time with 128 + signal.
void check_stops(igi::testing::ChildProcess& child, int signal, std::chrono::milliseconds limit) {
  // Still running: the signal finds it at work.
  const std::optional<igi::testing::ChildExit> early = child.wait_for(busy);
  INFO("before the signal the program ended with " << (early ? early->describe() : std::string("-")));
  REQUIRE_FALSE(early.has_value());
  child.send(signal);
  const auto sent = std::chrono::steady_clock::now();
  const std::optional<igi::testing::ChildExit> exit = child.wait_for(limit);
  const auto taken = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - sent);
  INFO("signal " << signal << " sent; " << taken.count() << " ms later the program "
                 << (exit ? "ended with " + exit->describe() : std::string("was still running")));
  REQUIRE(exit.has_value());
  CHECK(exit->exited);
  CHECK(exit->code == 128 + signal);
}

}  // namespace

TEST_CASE("signals: igi-render stops between frames on SIGTERM and SIGINT, writing nothing", "[programs]") {
  for (const int signal : {SIGTERM, SIGINT}) {
    const fs::path dir = scratch("render_between_" + std::to_string(signal));
    // Many small frames: the signal comes between two of them.
    igi::testing::ChildProcess render(IGI_RENDER_EXE, {"--builtin", "cornell", "--size", "64x48", "--vpls", "4",
                                                       "--frames", "100000", "-o", (dir / "never.png").string()});
    check_stops(render, signal, promised);
    CHECK(files_in(dir).empty());
    fs::remove_all(dir);
  }
}

TEST_CASE("signals: igi-render stops inside a long frame on SIGTERM, writing nothing", "[programs]") {
  const fs::path dir = scratch("render_inside");
  // One frame of many seconds (16 M pixels x 256 VPLs): the signal comes in the middle of it.
  igi::testing::ChildProcess render(IGI_RENDER_EXE, {"--builtin", "cornell", "--size", "4096x4096", "--vpls", "256",
                                                     "--frames", "1", "-o", (dir / "never.png").string()});
  check_stops(render, SIGTERM, promised);
  CHECK(files_in(dir).empty());
  fs::remove_all(dir);
}

TEST_CASE("signals: igi-render's path tracer stops on SIGTERM, writing nothing", "[programs]") {
  const fs::path dir = scratch("render_path");
  igi::testing::ChildProcess render(IGI_RENDER_EXE, {"--builtin", "cornell", "--size", "64x48", "--integrator", "path",
                                                     "--spp", "100000", "-o", (dir / "never.exr").string()});
  check_stops(render, SIGTERM, promised);
  CHECK(files_in(dir).empty());
  fs::remove_all(dir);
}

#ifdef IGI_VIEW_EXE
TEST_CASE("signals: igi-view stops on SIGTERM and SIGINT", "[programs]") {
  for (const int signal : {SIGTERM, SIGINT}) {
    // SDL's window-less video driver: the window is real to SDL, no display needed.
    igi::testing::ChildProcess view(IGI_VIEW_EXE, {"--builtin", "cornell", "--size", "64x48", "--frames", "0"},
                                    {"SDL_VIDEODRIVER=dummy", "LSAN_OPTIONS=detect_leaks=0"});
    check_stops(view, signal, promised);
  }
}
#endif

#if defined(IGI_CLUSTER_EXE) && defined(IGI_MPIEXEC)
TEST_CASE("signals: igi-cluster under mpirun stops on SIGTERM, writing nothing", "[programs]") {
  const std::string mpiexec = IGI_MPIEXEC;
  if (mpiexec.empty() || !fs::exists(mpiexec)) {
    WARN("skipped: mpirun not found (Open MPI missing)");
    return;
  }
  const fs::path dir = scratch("cluster");
  std::vector<std::string> arguments{"--oversubscribe", "-x", "LSAN_OPTIONS=detect_leaks=0"};
  if (::geteuid() == 0) arguments.push_back("--allow-run-as-root");
  for (const char* a : {"-np", "3", IGI_CLUSTER_EXE, "--builtin", "cornell", "--size", "64x48", "--vpls", "4",
                        "--frames", "100000", "-o"})
    arguments.push_back(a);
  arguments.push_back((dir / "never.png").string());
  igi::testing::ChildProcess cluster(mpiexec, arguments);
  // mpirun passes SIGTERM on to every rank and then reports their end; its own start (about a
  // second) comes before the ranks are busy, and its teardown after they end.
  const std::optional<igi::testing::ChildExit> early = cluster.wait_for(busy + 1500ms);
  INFO("before the signal mpirun ended with " << (early ? early->describe() : std::string("-")));
  REQUIRE_FALSE(early.has_value());
  cluster.send(SIGTERM);
  const std::optional<igi::testing::ChildExit> exit = cluster.wait_for(promised + 2000ms);
  INFO("mpirun " << (exit ? "ended with " + exit->describe() : std::string("was still running")) << " after SIGTERM");
  REQUIRE(exit.has_value());
  CHECK_FALSE((exit->exited && exit->code == 0));
  CHECK(files_in(dir).empty());
  fs::remove_all(dir);
}
#endif
