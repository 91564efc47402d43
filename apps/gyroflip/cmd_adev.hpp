/// \file
/// \brief `gyroflip adev` and `gyroflip noise`: options and entry points.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "commands.hpp"
#include "gyroflip/analysis/phase_source.hpp"
#include "gyroflip/io/series.hpp"
#include "gyroflip/report/figure.hpp"
#include "progress_bar.hpp"

namespace gyroflip::app {

/// Input options shared by `adev` and `noise`.
struct series_input {
  std::string file;
  std::string column = "rate_dps";  // a name, a number from 1, or several: a,b,c
  std::string columns;              // all-numeric: every numeric column but the time stamps
  double rate_hz = std::numeric_limits<double>::quiet_NaN();  // NaN: from time_s
  std::string input = "rate";                                 // rate | angle
  std::string dataset;                                        // HDF5 dataset path
  bool ignore_flip = false;  // analyse a column that switches with angle_deg all the same
  // How a logger wrote the file (docs/FORMATS.md, "CSV rules", "Time stamps").
  std::string delimiter;  // empty: detect; , ; tab space
  std::string decimal = ".";
  bool no_header = false;
  std::string time_column;  // empty: time_s
  std::string time_unit = "s";
  std::string gaps = "error";   // error | split | fill
  std::string topic;            // a ROS bag's sensor_msgs/Imu topic (empty: its only one)
  std::string units = "deg/s";  // of the samples: deg/s | rad/s | deg/h (angle: deg | rad)
  bool units_given = false;     // --units was given (noise: else a column's name may state it)
};

/// Degrees per second (or, for angle input, degrees) per unit of the samples.
[[nodiscard]] double deg_per_unit(const series_input& in);
/// The samples' unit as written in outputs ("deg/s", "rad/s", "deg/h"; "deg", "rad").
[[nodiscard]] std::string unit_name(const series_input& in);
/// "mtotdev, ttotdev and htotdev": the kinds Stable32's bias correction applies to
/// (analysis::dev_table), for help and messages.
std::string bias_corrected_kinds();

/// The unit of statistic `kind` ("oadev", "mtie", ...) of these samples, as `# units`, JSON
/// `units` and the plot's axis give it: the rate unit for the frequency-like deviations, the angle
/// unit for TDEV, TTOTDEV, MTIE and TIE rms ("deg/h*s" for those of deg/h samples).
[[nodiscard]] std::string dev_unit(const series_input& in, std::string_view kind);

/// A series ready for analysis: the samples and their phase source (which reads them).
struct analysis_input {
  io::series series;
  analysis::phase_source phase;
  std::string column;  ///< as the user named it
  /// A `.gfr` series with gaps read for pooling (load_series's `pool_gaps`, `--gaps split`):
  /// every gap-free stretch, each ready for analysis (`series` is then the longest); empty
  /// otherwise.
  std::vector<analysis_input> parts;
};
/// Opens `in.file` (CSV columns, .npy, raw float64 or HDF5) and prepares the phase of each column
/// asked for (`--column a,b,c`, `--columns all-numeric`: one pass over a CSV) for `in.input`
/// (two passes over the samples for rate input, with a progress line on a terminal).
/// `pool_gaps` (noise): a `.gfr` series with gaps under `--gaps split` also gets its gap-free
/// stretches (analysis_input::parts), which noise pools instead of analysing the longest alone.
result<std::vector<analysis_input>> load_series(const series_input& in, bool pool_gaps = false);

struct adev_options {
  series_input in;
  std::string kind = "oadev";
  std::string taus = "octave";
  std::string ci;  ///< two-sided level, "none", or empty: not given (0.683 where it applies)
  std::optional<int> alpha;  ///< a known noise type for the intervals (else identified per tau)
  bool ci_guard = false;     ///< no interval narrower than its neighbours allow (edf_rule::guarded)
  bool bias_correction = false;     ///< Stable32's bias correction of mtotdev/ttotdev/htotdev
  std::string dynamic;              ///< WINDOW_S[:STEP_S]: DAVAR, one curve per sliding window
  bool codev = false;               ///< GCODEV of two columns
  bool three_cornered_hat = false;  ///< clocks A, B, C from the columns AB, BC, CA
  bool json = false;
  std::string output;
  std::string plot;  ///< FILE.png|.svg|.pdf: the Allan plot, its .gp script and data beside it
};
int run_adev(const adev_options& o);

}  // namespace gyroflip::app

namespace gyroflip::app {

/// The names of the columns `in` asks for (`--columns all-numeric`: read from the file).
[[nodiscard]] result<std::vector<std::string>> column_names(const series_input& in);

/// `--plot FILE.png|.svg|.pdf` of adev and noise: the folder, the stem and the format.
struct plot_file {
  std::string dir, stem;
  report::image_format format;
};
/// The plot file `path` names (nullopt for ""); a usage error for another suffix.
[[nodiscard]] result<std::optional<plot_file>> plot_target(const std::string& path);

struct noise_options {
  series_input in;
  std::string plot;        ///< FILE.png|.svg|.pdf: the Allan plot with the fitted terms
  std::string plot_units;  ///< deg/h, deg/s, rad/s; m/s^2, mg, ug (empty: deg/h or mg)
  std::string title;       ///< the plot's title (default: the file's name)
  bool long_taus = false;  ///< also OADEV up to m <= (N-1)/2, shown not fitted
  double ci = 0.683;       ///< two-sided confidence level of the terms' intervals
  bool json = false;
  std::string kalibr;        ///< write Kalibr's IMU noise YAML here
  std::string kalibr_other;  ///< the other sensor's record for the Kalibr file
  std::string quantity;      ///< gyro | accel (empty: from each column's name, else gyro)
  std::string fit_taus;      ///< LO:HI (s): the range the model is fitted to (empty: all)
  std::string output;        ///< the terms as CSV, or JSON for FILE.json
};
int run_noise(const noise_options& o);

}  // namespace gyroflip::app
