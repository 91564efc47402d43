/// \file
/// \brief How the library reports the progress of long work: a callback, never a drawing.
///
/// The library never prints. A long pass (reading a big file, an Allan sweep) calls
/// `on_progress(done, total)` now and then from the caller's thread; the CLI turns that into
/// its terminal line (apps/gyroflip/progress_bar.hpp), a script or a GUI into whatever it likes.
/// A callback may throw to cancel the work (the Python module does on Ctrl-C): the library
/// starts nothing more, joins its threads, frees what it holds and lets the exception through.
#pragma once

#include <cstddef>
#include <functional>

namespace gyroflip {

/// Progress of a long pass: `done` of `total` units (any unit; total > 0). Called from the
/// caller's thread only; may be empty (no report).
using progress_fn = std::function<void(std::size_t done, std::size_t total)>;

}  // namespace gyroflip
