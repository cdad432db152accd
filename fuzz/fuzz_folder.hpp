// The private folder of a fuzz target that reads files (the readers take
// paths, so the bytes go through files): under /dev/shm when it exists
// (memory, no disk), one per target and process, removed again when the
// process exits normally; and the write of one input into it.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>

namespace chatter::fuzz {

class Folder {
 public:
  explicit Folder(const std::string& target) {
    namespace fs = std::filesystem;
    const fs::path base = fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
    dir_ = base / ("chatter_fuzz_" + target + "_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  ~Folder() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  Folder(const Folder&) = delete;
  Folder& operator=(const Folder&) = delete;
  const std::filesystem::path& path() const { return dir_; }

 private:
  std::filesystem::path dir_;
};

/// Writes `bytes` to `file` (replacing it); aborts when it cannot (the
/// target's environment, not its input, is broken).
inline void write_input(const std::filesystem::path& file, std::string_view bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", file.c_str());
    std::abort();
  }
}

}  // namespace chatter::fuzz
