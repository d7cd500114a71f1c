#pragma once
/// \file
/// Thin MPI helpers for the tile farm: error checks that throw, an RAII session, and waits that
/// poll with short sleeps instead of spinning (Open MPI's blocking calls busy-wait, which would
/// steal a core from the workers when ranks share a machine, as they do on a test box).

#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>

#include <mpi.h>

#include "igi/distributed/messages.hpp"

namespace igi {

/// Sleep between polls of an idle rank: 50 microseconds is about Linux's shortest real sleep and
/// adds under 1% to a tile that renders in several milliseconds.
inline constexpr std::chrono::microseconds mpi_poll_interval{50};

/// Throws DistributedError naming `what` and MPI's message unless `code` is MPI_SUCCESS.
inline void check_mpi(int code, const char* what) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw DistributedError(std::string(what) + " failed: " + std::string(text, std::size_t(length)));
}

/// Initialises MPI (threads funnelled through the main thread) and finalises it on destruction.
class MpiSession {
 public:
  /// Calls MPI_Init_thread with the program's arguments.
  MpiSession(int& argc, char**& argv) {
    int provided = 0;
    check_mpi(MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
    // Errors come back as codes so check_mpi can turn them into exceptions with a message.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  }
  MpiSession(const MpiSession&) = delete;             ///< One session per process: not copyable.
  MpiSession& operator=(const MpiSession&) = delete;  ///< Not assignable.
  /// Calls MPI_Finalize.
  ~MpiSession() { MPI_Finalize(); }
  /// This process's rank in MPI_COMM_WORLD.
  int rank() const {
    int rank = 0;
    check_mpi(MPI_Comm_rank(MPI_COMM_WORLD, &rank), "MPI_Comm_rank");
    return rank;
  }
  /// Processes in MPI_COMM_WORLD.
  int size() const {
    int size = 0;
    check_mpi(MPI_Comm_size(MPI_COMM_WORLD, &size), "MPI_Comm_size");
    return size;
  }
  /// Ends every rank after an error on one (a clean exit would leave the others waiting forever).
  [[noreturn]] static void abort(int code) {
    MPI_Abort(MPI_COMM_WORLD, code);
    std::exit(code);
  }
};

/// Waits for `request` to complete, sleeping between tests.
inline void wait_polling(MPI_Request& request, const char* what) {
  for (;;) {
    int done = 0;
    check_mpi(MPI_Test(&request, &done, MPI_STATUS_IGNORE), what);
    if (done) return;
    std::this_thread::sleep_for(mpi_poll_interval);
  }
}

/// Waits until a message from `source` with `tag` (wildcards allowed) can be received; returns its status.
inline MPI_Status probe_polling(int source, int tag, MPI_Comm comm) {
  for (;;) {
    int ready = 0;
    MPI_Status status;
    check_mpi(MPI_Iprobe(source, tag, comm, &ready, &status), "MPI_Iprobe");
    if (ready) return status;
    std::this_thread::sleep_for(mpi_poll_interval);
  }
}

/// Receives the probed message as bytes.
inline std::vector<std::uint8_t> receive_bytes(const MPI_Status& probed, MPI_Comm comm) {
  int count = 0;
  check_mpi(MPI_Get_count(&probed, MPI_BYTE, &count), "MPI_Get_count");
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(count));
  check_mpi(MPI_Recv(bytes.data(), count, MPI_BYTE, probed.MPI_SOURCE, probed.MPI_TAG, comm, MPI_STATUS_IGNORE),
            "MPI_Recv");
  return bytes;
}

/// Broadcasts a byte buffer from `root` (size first, then bytes), polling; others get it resized.
inline void broadcast_bytes(std::vector<std::uint8_t>& bytes, int root, MPI_Comm comm) {
  std::uint64_t size = bytes.size();
  MPI_Request request;
  check_mpi(MPI_Ibcast(&size, 1, MPI_UINT64_T, root, comm, &request), "MPI_Ibcast");
  wait_polling(request, "MPI_Ibcast of a message size");
  bytes.resize(std::size_t(size));
  if (size == 0) return;
  check_mpi(MPI_Ibcast(bytes.data(), int(size), MPI_BYTE, root, comm, &request), "MPI_Ibcast");
  wait_polling(request, "MPI_Ibcast of a message");
}

}  // namespace igi
