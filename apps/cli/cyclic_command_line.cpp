#include "cyclic_command_line.hpp"

namespace dem::cli {

std::optional<CyclicCommandLine> parse_cyclic_command_line(int argc, char** argv, std::ostream& out) {
  auto specimen = parse_shear_command_line(
      argc, argv, "dem-cyclic-shear",
      "cyclic and multidirectional simple shear (stress or strain control, constant volume or drained) on a specimen "
      "generated and consolidated here or read with --from (a consolidated restart)",
      out, lab::cyclic_shear_schema(), "runs/cyclic-shear");
  if (!specimen) return std::nullopt;
  lab::CyclicShearConfig cyclic = lab::cyclic_shear_config(*specimen->configuration);
  return CyclicCommandLine{std::move(*specimen), std::move(cyclic)};
}

}  // namespace dem::cli
