// The World the restart-file target loads into, shared with make_seeds so that seed files carry
// the same laws: every contact kind uses the rolling linear law, as in SimpleShearTest.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include <dem/dem.hpp>
#include <dem/io/checkpoint.hpp>

namespace dem::fuzz {

inline World checkpoint_world() {
  WorldSettings settings;
  settings.threads = 1;  // fuzzing runs one input at a time; threads would only add noise
  World world(settings);
  const auto sand = RollingLinearLaw::Params::deformable(5.3e7, 1.0, 0.45, 0.18);
  world.set_contact_model(ContactKind::BallBall, make_contact_model<RollingLinearLaw>(sand, "ball_ball"));
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<RollingLinearLaw>(sand, "ball_facet"));
  world.set_contact_model(ContactKind::BallPebble, make_contact_model<RollingLinearLaw>(sand, "ball_pebble"));
  return world;
}

// The restart-file frame, written here from the format description in io/checkpoint.hpp (magic,
// version, payload size, payload, checksum of the payload): the target wraps fuzzed payloads in
// a valid frame so that mutations reach io::read_world_state instead of stopping at the checksum.
inline constexpr std::string_view checkpoint_magic = "LIBDEMCK";
inline constexpr std::size_t checkpoint_header = 8 + 4 + 8;

// FNV-1a as io/checkpoint.cpp computes it. Its start value is 1469598103934665603, not the
// standard FNV-1a offset basis 14695981039346656037 (one digit shorter); files carry that value,
// so it is part of the format.
inline std::uint64_t fnv1a64(std::string_view bytes) {
  std::uint64_t hash = 1469598103934665603ULL;
  for (const unsigned char c : bytes) hash = (hash ^ c) * 0x100000001b3ULL;
  return hash;
}

template <class T>
void append_raw(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

inline std::string frame_checkpoint(std::string_view payload) {
  std::string file(checkpoint_magic);
  append_raw(file, io::checkpoint_format_version);
  append_raw(file, static_cast<std::uint64_t>(payload.size()));
  file.append(payload);
  append_raw(file, fnv1a64(payload));
  return file;
}

}  // namespace dem::fuzz
