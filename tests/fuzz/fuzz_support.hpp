// Shared by the fuzz targets (tests/fuzz/README.md). The rule every target enforces: a bad input
// ends in dem::InputError with a message; any other exception escaping the library is a bug, so
// the target prints it and aborts, which libFuzzer and the corpus replay both report as a crash.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <typeinfo>
#include <unistd.h>

#include <dem/core/errors.hpp>

namespace dem::fuzz {

[[noreturn]] inline void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz target: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

inline void check(bool ok, const std::string& what) {
  if (!ok) fail(what);
}

/// The scratch folder of this process, removed at exit. The readers under test take paths, so
/// each input goes through a file; /dev/shm keeps that in memory (override: LIBDEM_FUZZ_TMP).
inline const std::filesystem::path& scratch_dir() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path base;
    if (const char* env = std::getenv("LIBDEM_FUZZ_TMP")) base = env;
    else if (std::filesystem::is_directory("/dev/shm")) base = "/dev/shm";
    else base = std::filesystem::temp_directory_path();
    const auto d = base / ("libdem_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(scratch_dir(), ignored);
    });
    return d;
  }();
  return dir;
}

inline std::filesystem::path scratch(const std::string& name) { return scratch_dir() / name; }

inline void write_bytes(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  check(static_cast<bool>(out), "cannot write the scratch file " + path.string());
}

/// Runs `body`; InputError is the expected way to refuse an input (its message must say
/// something, and contain `must_mention` if given). Everything else aborts.
template <class Body>
bool refuses_cleanly(Body&& body, const std::string& must_mention = {}) {
  try {
    body();
    return false;
  } catch (const InputError& e) {
    const std::string message = e.what();
    check(!message.empty(), "InputError with an empty message");
    check(must_mention.empty() || message.find(must_mention) != std::string::npos,
          "InputError does not name '" + must_mention + "': " + message);
    return true;
  } catch (const std::exception& e) {
    fail(std::string("unexpected exception ") + typeid(e).name() + ": " + e.what());
  } catch (...) {
    fail("unexpected exception of a non-standard type");
  }
}

}  // namespace dem::fuzz
