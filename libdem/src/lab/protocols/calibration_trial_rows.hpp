// The rows of a calibration's trials: trials.csv and each trial's result.csv (by column name), and
// the bytes that carry them between processes bit for bit. Private to lab/protocols/calibration*.cpp.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <dem/lab/protocols/calibration.hpp>

namespace dem::lab::detail {

/// The trials as the bytes of their columns' doubles, one after another.
std::string trials_bytes(const std::vector<TrialResult>& trials);
std::vector<TrialResult> trials_from_bytes(const std::string& bytes);

/// Rows of trials.csv (or of a trial folder's result.csv), each column found by its name; the
/// modulus column is named `modulus_key` (effective_modulus or youngs_modulus).
std::vector<TrialResult> read_trial_rows(const std::filesystem::path& file, const std::string& modulus_key);
void write_trial_rows(const std::filesystem::path& file, const std::vector<TrialResult>& rows, const std::string& modulus_key);

}  // namespace dem::lab::detail
