/// \file
/// \brief One `# key: value` line of a recording's metadata (docs/FORMATS.md): what a CSV's
/// comment lines, a `.gfr`'s META and INFO, and a simulation say about the run.
#pragma once

#include <cstddef>
#include <string>

namespace gyroflip {

struct metadata_entry {
  std::string key;
  std::string value;
  std::size_t line = 0;    ///< where a CSV has it (1-based; 0: not from a file's line)
  std::size_t column = 0;  ///< the column of its value's first character (1-based; 0: unknown)
};

}  // namespace gyroflip
