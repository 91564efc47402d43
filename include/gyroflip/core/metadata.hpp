/// \file
/// \brief One `# key: value` line of a recording's metadata (docs/FORMATS.md): what a CSV's
/// comment lines, a `.gfr`'s META and INFO, and a simulation say about the run.
#pragma once

#include <string>

namespace gyroflip {

struct metadata_entry {
  std::string key;
  std::string value;
};

}  // namespace gyroflip
