/// \file
/// \brief The paper's experiment on the simulator (module workflow; docs/REPRODUCE.md): the
/// campaigns of Tab. 3 and 4 and the runs of Figs 3-10, on every core, set beside the paper's
/// numbers. What `gyroflip reproduce` and Python's `gyroflip.reproduce` run.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gyroflip/core/progress.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/sensor/presets.hpp"

namespace gyroflip::workflow {

struct reproduce_request {
  bool quick = false;      ///< one campaign (unless `campaigns`), runs a quarter as long
  std::uint64_t seed = 1;  ///< seed of the first campaign
  /// How many campaigns, 1 to max_campaigns; none: 10 (1 when quick).
  std::optional<std::size_t> campaigns;
  std::string output;  ///< a report folder for the page (empty: none)
  /// Sensor models used instead of the built-in presets of the same name ("adxrs150",
  /// "hz1-90-100a"): a model to put to the paper's test. Nothing of a given model was fitted
  /// here, so every number the preset was fitted to (its tables' mean and std of dN, the HZ1's
  /// per-cycle std) is a test of it too, and a model whose predictions are wrong fails the
  /// verdict; except a comparison that rests on a value the preset fitted to the paper and the
  /// model kept (sensor::fitted_to_paper, the preset's value): a calibration target, not counted.
  std::vector<sensor::preset> sensors;
  /// Sensor models read from TOML preset files (docs/SIMULATOR.md), as `sensors`: the paper's
  /// sensor `name` ("adxrs150" or "hz1-90-100a") and the file. Each file is listed in the
  /// page's provenance with its size and SHA-256.
  struct sensor_file {
    std::string name;
    std::string path;
  };
  std::vector<sensor_file> sensor_files;
  /// Run the sensitivity study (docs/REPRODUCE.md, "Sensitivity"): the experiment again, one
  /// campaign each, with each assumed value changed within reason. Default: unless quick.
  std::optional<bool> sensitivity;
  std::string command;  ///< the command (or call) exactly as run, for the provenance
  std::string made_by = "gyroflip reproduce";  ///< who made the folder
};

/// The most campaigns a reproduction runs.
inline constexpr std::size_t max_campaigns = 1000;

struct reproduction {
  std::string text;          ///< the comparison as plain text
  std::string summary_json;  ///< summary.json's text (schema gyroflip.reproduce/N)
  /// The verdict: every prediction of the model (a quantity the simulator predicts from values
  /// not fitted to the data it is compared with, and compared with data not used in any fit)
  /// within its criterion, none so close to its limit that the seed decides it, none missed
  /// within the chance of so many tests (docs/REPRODUCE.md, "The verdict"). The calibration
  /// targets (fitted) and the comparisons with data the model was fitted to are shown but not
  /// counted.
  bool reproduced = false;
};

/// Runs the reproduction (all simulated runs on every core through the library's parallel
/// helper; progress in runs) and, with request.output, writes its report folder (checked before
/// the simulations). Errors: campaigns outside 1..max_campaigns (parameter `campaigns`), a
/// sensor model named other than one of the paper's sensors or given twice (parameter
/// `sensors`), a sensor file that cannot be read or parsed (its file, line and column), the
/// folder's, a simulation that fails, gnuplot or the PDF makers missing.
[[nodiscard]] result<reproduction> reproduce(const reproduce_request& request,
                                             const progress_fn& on_progress = {});

}  // namespace gyroflip::workflow
