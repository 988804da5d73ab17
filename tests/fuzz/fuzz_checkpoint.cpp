// Fuzz target: the restart-file reader, io::load_checkpoint into a World with the simple-shear
// laws. First byte even: the rest is the file as it is (damaged frames, wrong versions, bad
// checksums). Odd: the rest is a payload that gets a valid frame and checksum, so that mutations
// exercise io::read_world_state itself, as a file written by a buggy or foreign writer would.
// An accepted state must then step without crashing: read_world_state validates indices for that.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <typeinfo>

#include "checkpoint_world.hpp"
#include "fuzz_support.hpp"

using namespace dem;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string_view rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  const auto file = fuzz::scratch("input.restart");
  fuzz::write_bytes(file, (data[0] & 1) ? fuzz::frame_checkpoint(rest) : std::string(rest));
  World world = fuzz::checkpoint_world();
  if (fuzz::refuses_cleanly([&] { (void)io::load_checkpoint(file, world); }, file.string())) return 0;
  try {
    world.step(2);
  } catch (const InputError&) {
  } catch (const InstabilityError&) {  // absurd but consistent states may blow up: that is caught
  } catch (const std::exception& e) {
    fuzz::fail(std::string("stepping a loaded state threw ") + typeid(e).name() + ": " + e.what());
  }
  return 0;
}
