#include <dem/io/checkpoint.hpp>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include <dem/base/input_file.hpp>
#include <dem/core/errors.hpp>
#include <dem/io/atomic_file.hpp>
#include <dem/io/world_state.hpp>

namespace dem::io {

namespace {

constexpr char magic[8] = {'L', 'I', 'B', 'D', 'E', 'M', 'C', 'K'};

/// FNV-1a, 64 bit: detects truncation and bit flips; not a cryptographic guarantee.
std::uint64_t checksum(const std::string& data) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : data) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  return h;
}

template <class T>
void put(std::ostream& out, const T& v) {
  out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}

}  // namespace

void save_checkpoint(const std::filesystem::path& path, const World& world, const std::string& protocol_state) {
  std::ostringstream payload(std::ios::binary);
  const std::uint64_t text_size = protocol_state.size();
  put(payload, text_size);
  payload.write(protocol_state.data(), static_cast<std::streamsize>(text_size));
  write_world_state(payload, world);
  const std::string data = payload.str();
  write_atomically_binary(path, [&](std::ostream& out) {
    out.write(magic, sizeof magic);
    put(out, checkpoint_format_version);
    put(out, static_cast<std::uint64_t>(data.size()));
    out.write(data.data(), static_cast<std::streamsize>(data.size()));
    put(out, checksum(data));
  });
}

namespace {

// A restart file checked whole: its format version, its payload (protocol text, then world state)
// and the protocol text read from the payload's start.
struct Checkpoint {
  std::uint32_t version = 0;
  std::string data;
  std::string text;
  std::size_t world_offset = 0;  // where the world state starts in data
};

Checkpoint read_framed(const std::filesystem::path& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    throw InputError("restart file " + path.string() + " is a folder: give the restart file in it, e.g. " +
                     (path / "consolidated.restart").string() + " or " + (path / "restart.restart").string());
  require_input_file(path, "restart file", "a libdem restart file", max_restart_file_bytes);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("restart file " + path.string() + ": cannot be opened");
  const std::string file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t header = sizeof magic + sizeof(std::uint32_t) + sizeof(std::uint64_t);
  if (file.size() < sizeof magic || file.compare(0, sizeof magic, magic, sizeof magic) != 0)
    throw InputError("restart file " + path.string() + ": not a libdem restart file");
  if (file.size() < header + sizeof(std::uint64_t))
    throw InputError("restart file " + path.string() + ": truncated (" + std::to_string(file.size()) +
                     " bytes, a restart file has at least " + std::to_string(header + sizeof(std::uint64_t)) + ")");
  std::uint32_t version = 0;
  std::uint64_t size = 0, stored = 0;
  std::memcpy(&version, file.data() + sizeof magic, sizeof version);
  std::memcpy(&size, file.data() + sizeof magic + sizeof version, sizeof size);
  if (version < 1 || version > checkpoint_format_version)
    throw InputError("restart file " + path.string() + ": format version " + std::to_string(version) +
                     ", this libdem reads versions 1 to " + std::to_string(checkpoint_format_version));
  // Shorter and longer than the header says are told apart: bytes appended after a complete
  // file (a copy that went wrong) are not a truncation.
  const std::uint64_t present = file.size() - header - sizeof stored;
  if (size > present)
    throw InputError("restart file " + path.string() + ": truncated (" + std::to_string(file.size()) +
                     " bytes, the header promises a payload of " + std::to_string(size) + " bytes, " +
                     std::to_string(present) + " are there)");
  if (size < present)
    throw InputError("restart file " + path.string() + ": too long (" + std::to_string(file.size()) + " bytes, " +
                     std::to_string(present - size) + " bytes past the end of the " +
                     std::to_string(header + size + sizeof stored) + "-byte restart file): must end at its checksum");
  Checkpoint c;
  c.version = version;
  c.data = file.substr(header, size);
  const std::string& data = c.data;
  std::memcpy(&stored, file.data() + header + size, sizeof stored);
  if (checksum(data) != stored) throw InputError("restart file " + path.string() + ": checksum mismatch (corrupted)");
  std::istringstream payload(data, std::ios::binary);
  std::uint64_t text_size = 0;
  payload.read(reinterpret_cast<char*>(&text_size), sizeof text_size);
  if (!payload || text_size > data.size() - sizeof text_size)
    throw InputError("restart file " + path.string() + ": protocol state size = " + std::to_string(text_size) +
                     ": must be at most " + std::to_string(data.size() - std::min(data.size(), sizeof text_size)) +
                     " bytes (the payload)");
  c.text.assign(text_size, '\0');
  payload.read(c.text.data(), static_cast<std::streamsize>(text_size));
  c.world_offset = static_cast<std::size_t>(payload.tellg());
  return c;
}

}  // namespace

std::string read_checkpoint_protocol(const std::filesystem::path& path) { return read_framed(path).text; }

std::string load_checkpoint(const std::filesystem::path& path, World& world) {
  const Checkpoint c = read_framed(path);
  std::istringstream payload(c.data, std::ios::binary);
  payload.seekg(static_cast<std::streamoff>(c.world_offset));
  const std::string& data = c.data;
  const std::uint32_t version = c.version;
  try {
    read_world_state(payload, world, version);
  } catch (const InputError& e) {
    throw InputError("restart file " + path.string() + ": " + e.what());
  }
  // The payload is exactly the protocol state and the world state: anything after it means the
  // writer and this reader disagree about the format.
  const auto used = static_cast<std::size_t>(payload.tellg());
  if (used != data.size())
    throw InputError("restart file " + path.string() + ": " + std::to_string(data.size() - used) +
                     " bytes after the world state: must be none (written by another format?)");
  return c.text;
}

}  // namespace dem::io
