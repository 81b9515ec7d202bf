// CARMEN reader: any bytes, plain or compressed, read leniently through ScanStream (the path of
// `pslam run` and the agent's log source). It must end with records or a clear error, never crash.
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>

#include "pslam/io/carmen_reader.hpp"

namespace {

bool Compressed(const std::uint8_t* data, std::size_t size) {
  return (size >= 2 && data[0] == 0x1f && data[1] == 0x8b) ||
         (size >= 3 && data[0] == 'B' && data[1] == 'Z' && data[2] == 'h');
}

void ReadAll(pslam::CarmenReader& reader) {
  pslam::ScanStream stream(reader);
  while (stream.Next()) {
  }
  (void)reader.progress();
}

// gzip and bzip2 are detected from a file's magic bytes, so compressed input goes in as a file.
struct MemoryFile {
  int fd = memfd_create("carmen", 0);
  ~MemoryFile() {
    if (fd >= 0) close(fd);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const pslam::CarmenReaderOptions options;  // lenient, as `pslam run` and the agent read logs
  try {
    if (Compressed(data, size)) {
      MemoryFile file;
      if (file.fd < 0 || write(file.fd, data, size) != static_cast<ssize_t>(size)) return 0;
      pslam::CarmenReader reader("/proc/self/fd/" + std::to_string(file.fd), options);
      ReadAll(reader);
      return 0;
    }
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    pslam::CarmenReader reader(in, "fuzz.log", options);
    ReadAll(reader);
  } catch (const std::runtime_error&) {
    // A clear error (a damaged compressed stream) is a fine answer; anything else escapes and is a finding.
  }
  return 0;
}
