/// \file
/// \brief Command-line parsing for all subcommands: the only translation unit that includes
/// CLI11 (a 5-s header). Parsing only fills option structs; work runs after parsing.
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "cli.hpp"
#include "cmd_adev.hpp"
#include "cmd_emulate.hpp"
#include "cmd_plan.hpp"
#include "cmd_record.hpp"
#include "cmd_simulate.hpp"
#include "commands.hpp"
#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/text.hpp"
#include "gyroflip/method/demodulator.hpp"

namespace gyroflip::app {
namespace {

using action = std::function<int()>;

// A two-sided confidence level (`--ci` of adev and noise): a probability strictly inside (0, 1);
// for adev also `none` (no noise identification, no EDF, no bounds).
CLI::Validator confidence_level(bool allow_none) {
  return CLI::Validator(
      [allow_none](const std::string& text) -> std::string {
        if (allow_none && text == "none") return {};
        const auto v = text::to_double(text);
        if (v && analysis::check_confidence_level(*v)) return {};
        return std::string("must be a probability in (0, 1), e.g. 0.683") +
               (allow_none ? " or none" : "") + "; got " + text;
      },
      allow_none ? "LEVEL in (0,1) or none" : "LEVEL in (0,1)");
}

// A finite number (CLI11 reads "nan" and "inf" as doubles; a NaN would pass for "not given").
CLI::Validator finite_number() {
  return CLI::Validator(
      [](const std::string& text) -> std::string {
        const auto v = text::to_double(text);
        if (v && std::isfinite(*v)) return {};
        return "must be a finite number; got " + text;
      },
      "NUMBER");
}

// --seed: an integer 0 .. 2^64 - 1, digits only. CLI11 converts "-1" to an unsigned 64-bit option
// by wrapping it to 2^64 - 1, and 2^64 to 2^64 - 1 (review of issue 22, R10).
CLI::Option* add_seed(CLI::App* sub, std::uint64_t& seed, const std::string& help) {
  return sub->add_option("--seed", seed, help)
      ->check(CLI::Validator(
          [](const std::string& text) -> std::string {
            std::uint64_t v = 0;
            const char* end = text.data() + text.size();
            const auto [at, ec] = std::from_chars(text.data(), end, v);
            const bool digits = !text.empty() && text.front() != '-' && text.front() != '+';
            if (digits && ec == std::errc() && at == end) return {};
            return "must be an integer from 0 to 2^64 - 1; got " + text;
          },
          "UINT64"))
      ->capture_default_str();
}

// Binds options to a shared struct and, when the subcommand is chosen, selects its run_.
template <class Options, class Run>
std::shared_ptr<Options> bind(CLI::App* sub, action& chosen, Run run) {
  auto opts = std::make_shared<Options>();
  sub->callback([opts, &chosen, run] { chosen = [opts, run] { return run(*opts); }; });
  return opts;
}

void setup_earth(CLI::App& app, action& chosen) {
  auto* sub = app.add_subcommand("earth", "Earth-rate component along a sensitive axis (deg/s)");
  auto o = bind<earth_options>(sub, chosen, run_earth);
  sub->add_option("--latitude", o->lat_deg, "geodetic latitude (deg, north positive)")->required();
  sub->add_option("--axis", o->axis, "sensitive axis at 0 deg: north|east|down|up or N,E,D")
      ->capture_default_str();
  sub->add_flag("--json", o->json, "print one JSON object");
}

void setup_heading(CLI::App& app, action& chosen) {
  auto* sub = app.add_subcommand(
      "heading",
      "North finding: the azimuth of the sensitive axis at the table's 0 deg from indexed runs "
      "about a vertical table axis (>= 3 positions; 0/180 with the scale factor known: up to its "
      "sign), with its 1 sigma and the white-noise limit");
  auto o = bind<heading_options>(sub, chosen, run_heading);
  sub->add_option("runs", o->runs, "one recording, or two with the rig's base turned between")
      ->required();
  sub->add_option("--latitude", o->lat_deg, "geodetic latitude of the site (deg)")->required();
  sub->add_option("--table-axis", o->table_axis,
                  "up (table angles counter-clockwise seen from above) or down; default: the "
                  "recording's, else up")
      ->check(CLI::IsMember({"up", "down"}));
  sub->add_option("--base-turn", o->base_turn_deg,
                  "two runs: the rig's base turned clockwise by this (deg) from the first to the "
                  "second (default: from the recordings' azimuths)");
  sub->add_option("--sensor", o->sensor,
                  "adxrs150|hz1-90-100a|FILE.toml: print its dead-time bound beside the limit");
  sub->add_option("--harmonics", o->harmonics,
                  "1, or 2: fit the second harmonic too (>= 5 positions; docs/NORTH.md says "
                  "when it is warranted)")
      ->check(CLI::IsMember({1, 2}))
      ->capture_default_str();
  sub->add_flag("--json", o->json, "print one JSON object");
}

// The simulated coils' heat (simulate, emulate; docs/SIMULATOR.md §4).
void add_coil_heat(CLI::App* sub, std::string& spec) {
  sub->add_option("--coil-heat", spec,
                  "the coils warm the gyro: RISE_C[:TAU_S], the steady rise with the coils on "
                  "all the time and its time constant (default TAU 600 s; docs/SIMULATOR.md)");
}

// The rig's settings (rig_options.hpp) that `simulate` models and `record` sends in CONFIGURE.
// `device`: also those only the device acts on (--n-temp, --home); otherwise the simulated
// coils' heat (--coil-heat).
void add_rig_options(CLI::App* sub, rig_options& o, bool device) {
  sub->add_option("--n-avg", o.n_avg, "gyro conversions per dwell")->capture_default_str();
  if (device)
    sub->add_option("--n-temp", o.n_temp, "temperature conversions per dwell")
        ->capture_default_str();
  sub->add_option("--settle", o.settle_s, "settling time after a turn (s)")->capture_default_str();
  sub->add_option("--positions", o.positions,
                  device ? "the angle table: 2 to 8 table positions (deg, whole steps)"
                         : "the table positions A,B,... (2 to 8; deg, whole steps)")
      ->capture_default_str();
  sub->add_option("--filter-word", o.filter_word, "AD7739 filter word FW (2..127)")
      ->capture_default_str();
  sub->add_flag("--no-chop", o.no_chop, "AD7739 without chopping");
  sub->add_option("--steps-per-rev", o.steps_per_rev, "stepper full steps per table revolution")
      ->capture_default_str();
  sub->add_option("--step-rate", o.step_rate_sps, "stepper top rate (steps/s)")
      ->capture_default_str();
  sub->add_option("--start-rate", o.start_rate_sps, "stepper start rate (steps/s)")
      ->capture_default_str();
  sub->add_option("--accel", o.accel_sps2, "stepper ramp (steps/s^2)")->capture_default_str();
  sub->add_flag("--one-way", o.one_way, "always turn the same way (a rotary joint)");
  sub->add_flag("--hold-coils", o.hold_coils,
                "keep the stepper energised during dwells too (the default de-energises it while "
                "the gyro measures: held, the coils heat the table)");
  if (device) {
    sub->add_flag("--home", o.home, "find the home switch before the first cycle");
  } else {
    add_coil_heat(sub, o.coil_heat);
  }
}

// The rig's mount (physics_options.hpp, mount_of): simulate's and emulate's.
void add_mount_options(CLI::App* sub, std::optional<double>& azimuth_deg, double& tilt_mrad,
                       double& tilt_azimuth_deg) {
  sub->add_option("--azimuth", azimuth_deg,
                  "azimuth of the sensitive axis at the table's 0 deg (deg from north, "
                  "clockwise; horizontal; instead of --axis; north finding: --table-axis up)");
  sub->add_option("--tilt-mrad", tilt_mrad, "the rig's tilt: the table axis leans (mrad)")
      ->capture_default_str();
  sub->add_option("--tilt-azimuth", tilt_azimuth_deg,
                  "where the table axis leans (deg clockwise from the sensitive axis's azimuth "
                  "with --azimuth, else from north)")
      ->capture_default_str();
}

void setup_simulate(CLI::App& app, action& chosen) {
  auto* sub =
      app.add_subcommand("simulate", "Simulate a rig recording (sensor, turntable, AD7739)");
  auto o = bind<simulate_options>(sub, chosen, run_simulate);
  sub->add_option("--sensor", o->sensor, "adxrs150|hz1-90-100a|FILE.toml")->required();
  sub->add_option("--duration", o->duration_s, "run length (s)")->capture_default_str();
  sub->add_option("--temp", o->temp_c, "constant sensor temperature (degC; default: preset T_ref)");
  sub->add_option("--temp-profile", o->temp_profile,
                  "steps:T:C,...|ramp:FROM:TO:DUR_S|fridge:MEAN:SWING:PERIOD_S|FILE.csv");
  sub->add_option("--latitude", o->lat_deg, "geodetic latitude (deg)")->capture_default_str();
  sub->add_option("--axis", o->axis, "sensitive axis at 0 deg: north|east|down|up or N,E,D")
      ->capture_default_str();
  sub->add_option("--table-axis", o->table_axis,
                  "turntable axis (default: horizontal, perpendicular)");
  sub->add_option("--rate-profile", o->rate_profile,
                  "input rate: V|const:V|steps:T:V,...|sine:AMP:FREQ_HZ[:OFFSET] (deg/s)")
      ->capture_default_str();
  add_seed(sub, o->seed, "random seed");
  sub->add_flag("--raw", o->raw, "write every conversion (angle empty while turning and settling)");
  sub->add_option("-o,--output", o->out, "recording CSV (- = stdout)")->capture_default_str();
  sub->add_option("--truth", o->truth, "write the true terms per output row to this CSV");
  sub->add_flag("--no-flip", o->no_flip,
                "never turn: stay at position A (a stationary recording of the raw sensor)");
  sub->add_option("--power-on-before", o->power_on_before_s,
                  "sensor powered this long before the run (s; 0 = cold start)")
      ->capture_default_str();
  add_rig_options(sub, o->rig, false);
  sub->add_option("--order", o->order,
                  "visiting order: auto (two positions A,B,A,B; more: sweep), sweep (forwards "
                  "then backwards, each end twice), cycle (the table's order), there-and-back "
                  "(0,1,...,N-1,...,1: the device's order, record --order)")
      ->check(CLI::IsMember({"auto", "sweep", "cycle", "there-and-back"}))
      ->capture_default_str();
  add_mount_options(sub, o->azimuth_deg, o->tilt_mrad, o->tilt_azimuth_deg);
}

void setup_emulate(CLI::App& app, action& chosen) {
  auto* sub = app.add_subcommand(
      "emulate", "Run the rig's firmware against the simulated rig on a pty or serial port");
  auto o = bind<emulate_options>(sub, chosen, run_emulate);
  sub->add_option("--sensor", o->sensor, "adxrs150|hz1-90-100a|FILE.toml")->capture_default_str();
  sub->add_option("--temp", o->temp_c, "constant sensor temperature (degC; default: preset T_ref)");
  sub->add_option("--temp-profile", o->temp_profile,
                  "steps:T:C,...|ramp:FROM:TO:DUR_S|fridge:MEAN:SWING:PERIOD_S|FILE.csv");
  sub->add_option("--rate-profile", o->rate_profile,
                  "input rate: V|const:V|steps:T:V,...|sine:AMP:FREQ_HZ[:OFFSET] (deg/s)")
      ->capture_default_str();
  sub->add_option("--latitude", o->lat_deg, "geodetic latitude (deg)")->capture_default_str();
  sub->add_option("--axis", o->axis, "sensitive axis at 0 deg: north|east|down|up or N,E,D")
      ->capture_default_str();
  sub->add_option("--table-axis", o->table_axis,
                  "turntable axis (default: horizontal, perpendicular)");
  add_mount_options(sub, o->azimuth_deg, o->tilt_mrad, o->tilt_azimuth_deg);
  sub->add_option("--truth", o->truth,
                  "write the terms an indexed run should find (c1, s1 of the Earth term and "
                  "g-term over the table angle) to this JSON file");
  sub->add_option("--speed", o->speed, "X times real time, or max (as fast as the reader takes)")
      ->capture_default_str();
  sub->add_flag("--pty", o->pty, "open a pseudo-terminal and print its path");
  sub->add_option("--port", o->port, "an existing serial device");
  add_seed(sub, o->seed, "random seed");
  sub->add_option("--fault-ber", o->fault_ber, "bit error rate on the device's output")
      ->capture_default_str();
  sub->add_option("--fault-drop", o->fault_drop, "probability of a dropped output byte")
      ->capture_default_str();
  sub->add_option("--log", o->log, "write every DWELL the device sent to this CSV");
  sub->add_option("--link", o->link,
                  "keep this symbolic link pointing at the line (like /dev/serial/by-id)");
  sub->add_option(
         "--fault-reset-at", o->fault_reset_at_s,
         "reset the firmware at these device times (s after the first START; comma-separated)")
      ->delimiter(',');
  sub->add_option("--fault-unplug", o->fault_unplug,
                  "AT:FOR - AT device s after the first START the line vanishes for FOR device s "
                  "(repeatable; the rig runs on, its output is lost)");
  sub->add_option(
      "--fault-stall", o->fault_stall,
      "AT:FOR - after the first frame it sends from AT device s after the first START on, "
      "the emulator stops for FOR wall s, as under SIGSTOP: it neither reads nor "
      "sends, then catches up (repeatable)");
  sub->add_option(
      "--fault-tx-hold", o->fault_tx_hold,
      "AT:FOR - AT device s after the first START the device's UART transmitter is held for FOR "
      "device s (a stuck transmitter or CTS): frames that do not fit its transmit ring are "
      "dropped from the live stream and kept in its history, for RESEND (repeatable)");
  sub->add_option("--fault-lose-reply", o->fault_lose_reply,
                  "CMD:N or CMD:N-M - the reply (ACK or NAK; a PING's INFO too) to the Nth (to "
                  "Mth) CMD frame the device takes is lost on the line (CMD: ping, configure, "
                  "start, stop, ...; comma-separated)")
      ->delimiter(',');
  sub->add_option("--fault-reset-before", o->fault_reset_before,
                  "CMD:N or CMD:N-M - reset the firmware just before it takes the Nth (to Mth) "
                  "CMD frame (comma-separated)")
      ->delimiter(',');
  sub->add_flag("--fault-lose-boot-info", o->fault_lose_boot_info,
                "the INFO each boot sends is lost on the line (a reset goes unseen)");
  sub->add_option("--serial", o->serial,
                  "the emulated board's serial number in its INFO (default: a random non-zero "
                  "one, so that no two emulators look like one board; 0: a board whose "
                  "information flash holds no serial record)");
  sub->add_option("--duration", o->duration_s, "simulated seconds to run (0: until stopped)")
      ->capture_default_str();
  sub->add_option("--power-on-before", o->power_on_before_s,
                  "sensor powered this long before the run (s; 0 = cold start)")
      ->capture_default_str();
  sub->add_option("--filter-word", o->filter_word, "AD7739 filter word FW of the physics")
      ->capture_default_str();
  sub->add_flag("--no-chop", o->no_chop, "AD7739 without chopping");
  sub->add_option("--steps-per-rev", o->steps_per_rev, "stepper full steps per table revolution")
      ->capture_default_str();
  add_coil_heat(sub, o->coil_heat);
}

void setup_record(CLI::App& app, action& chosen, const std::vector<std::string>& args) {
  auto* sub = app.add_subcommand("record",
                                 "Record a rig run over a serial port into a crash-safe .gfr file");
  auto o = bind<record_options>(sub, chosen, run_record);
  o->command_line = args;
  sub->add_option("--port", o->port, "serial device of the rig (or an emulator's pty)")->required();
  sub->add_option("--baud", o->baud, "line rate (b/s)")->capture_default_str();
  sub->add_option("-o,--output", o->output, "the recording RUN.gfr (never overwritten)")
      ->required();
  sub->add_option("--duration", o->duration_s, "device-clock seconds to record (0: until Ctrl-C)")
      ->capture_default_str();
  sub->add_option("--sensor", o->sensor,
                  "adxrs150|hz1-90-100a|FILE.toml: its nominal scale factor converts to deg/s")
      ->capture_default_str();
  add_rig_options(sub, o->rig, true);
  sub->add_option(
         "--order", o->order,
         "visiting order, written into the device's angle table: auto (two positions "
         "A,B,A,B; three to five: there-and-back; more: cycle), cycle (the table's order), "
         "there-and-back (0,1,...,N-1,...,1: forwards, then back without a second dwell "
         "at the ends)")
      ->check(CLI::IsMember({"auto", "cycle", "there-and-back"}))
      ->capture_default_str();
  sub->add_flag("--raw", o->raw, "keep every gyro conversion (RAW frames)");
  sub->add_option("--table-axis", o->table_axis,
                  "the table's axis, stored in the recording for heading and calibrate: "
                  "up|down (north finding) or as simulate's (default: not recorded)");
  sub->add_option("--azimuth", o->azimuth_deg,
                  "azimuth of the sensitive axis at the table's 0 deg (deg from north, "
                  "clockwise), stored in the recording (default: not recorded)");
  sub->add_option("--reconnect-timeout", o->reconnect_timeout_s,
                  "how long to wait for a vanished port (s)")
      ->capture_default_str();
  sub->add_option("--temp-mv-per-c", o->temp_mv_per_c,
                  "temperature channel: mV per degC (ADXRS150 TEMP: 8.4)")
      ->capture_default_str();
  sub->add_option("--temp-at-0v", o->temp_at_0v_c,
                  "temperature channel: degC at 0 V against the reference (ADXRS150: 24.85)")
      ->capture_default_str();
  sub->add_flag("--json-progress", o->json_progress,
                "print progress as one JSON object per line on stdout");
}

void setup_export(CLI::App& app, action& chosen) {
  auto* sub = app.add_subcommand("export", "Write a .gfr rig recording as a recording CSV");
  auto o = bind<export_options>(sub, chosen, run_export);
  sub->add_option("file", o->file, "the rig recording RUN.gfr")->required();
  sub->add_option("-o,--output", o->output, "RUN.csv (- = stdout)")->required();
  sub->add_flag("--raw", o->raw, "one row per gyro conversion (a recording made with --raw)");
  sub->add_flag("--strict", o->strict,
                "refuse a recording with a damaged region instead of skipping it with a warning");
}

void setup_sensors(CLI::App& app, action& chosen) {
  auto* sub = app.add_subcommand("sensors", "List sensor presets with parameters, units, sources");
  auto o = bind<sensors_options>(sub, chosen, run_sensors);
  sub->add_option("--dead-time", o->dead_s,
                  "the dead time per turn (s) for the implied best dwell sqrt(d tau_c)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  sub->add_option("--latitude", o->lat_deg, "the latitude (deg) for the implied heading limit")
      ->check(CLI::Range(-85.0, 85.0))
      ->capture_default_str();
  sub->add_flag("--json", o->json, "print one JSON object");
}

// The recording rules `calibrate --help` and `compensate --help` state (docs/FORMATS.md).
constexpr const char* recording_rules =
    "Recording rules (CSV, docs/FORMATS.md): columns time_s, angle_deg, rate_dps (deg/s), "
    "optional temp_c and n_avg; one row per sample or per averaged dwell. A dwell is a run of "
    "rows with equal angle_deg; angle_deg is a position of the table of the '# positions_deg: "
    "A,B,...' line ('auto': the distinct angles), without it 0 or 180 only (an encoder angle "
    "within --angle-tolerance DEG of a position counts as it), and empty while the table turns; "
    "rows of the settling time after a turn are left out by the recorder (or give them an empty "
    "angle). Cycles need dwells at the position nearest 0 and at the one 180 deg from it (other "
    "positions are passed over). dN is half the difference of the rate at 0 deg and at 180 deg, "
    "Earth rate plus g-sensitivity term: dN = (r_0 - r_180) / 2 (paper eqns 8-11).";

void add_angle_tolerance(CLI::App* sub, double& tol) {
  sub->add_option(
         "--angle-tolerance", tol,
         "an encoder angle within DEG of a table position reads as that position (0 to 10)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  sub->footer(recording_rules);
}

void setup_calibrate(CLI::App& app, action& chosen) {
  auto* sub = app.add_subcommand("calibrate", "dN from stationary recordings (paper eqns 8-11)");
  auto o = bind<calibrate_options>(sub, chosen, run_calibrate);
  sub->add_option("files", o->files, "recordings (CSV, docs/FORMATS.md)");
  sub->add_option("--latitude", o->lat_deg, "latitude (deg) to split dN into Earth and g terms")
      ->check(finite_number());
  sub->add_option("--axis", o->axis, "sensitive axis at 0 deg: north|east|down|up or N,E,D");
  sub->add_option("--pairing", o->pairing, "cycle estimator")
      ->check(CLI::IsMember(gyroflip::method::scheme_names()))
      ->capture_default_str();
  auto* degree =
      sub->add_option("--degree", o->degree, "degree of the dN(T) polynomial (several files)")
          ->check(CLI::Range(0, 6))
          ->capture_default_str();
  sub->add_option("-o,--output", o->output, "write the calibration JSON to this file");
  sub->add_flag("--json", o->json, "print the calibration as one JSON object");
  sub->add_option("--sensor", o->sensor,
                  "sensor preset or FILE.toml whose g-sensitivity specification the stationarity "
                  "test checks (default: the recordings' preset)");
  sub->add_flag("--strict", o->strict,
                "refuse a run that fails the stationarity test (exit 2) instead of warning");
  add_angle_tolerance(sub, o->angle_tolerance_deg);
  sub->add_flag("--explain", o->explain,
                "say which terms an N-position run separates and which pairs no run does, "
                "before a run (--positions, --table-axis) or for the files, without calibrating");
  sub->add_option("--positions", o->positions, "with --explain: the table positions A,B,... (deg)");
  sub->add_option("--table-axis", o->table_axis,
                  "with --explain: the table axis (up|down: vertical; else horizontal); default "
                  "the recordings' `# table_axis:`, else horizontal");
  sub->parse_complete_callback([o, degree] { o->degree_given = degree->count() > 0; });
}

void setup_compensate(CLI::App& app, action& chosen) {
  auto* sub =
      app.add_subcommand("compensate", "Compensated rate per cycle, w = r - dN (paper eqn 12)");
  auto o = bind<compensate_options>(sub, chosen, run_compensate);
  sub->add_option("file", o->file, "recording (CSV, docs/FORMATS.md)")->required();
  auto* dn = sub->add_option("--delta-n", o->delta_n_dps, "dN to subtract (deg/s)");
  auto* cal = sub->add_option("--calibration", o->calibration,
                              "calibration JSON from `gyroflip calibrate -o`");
  dn->excludes(cal);
  sub->add_option("--pairing", o->pairing,
                  "cycle estimator (default: the calibration's, else abba)")
      ->check(CLI::IsMember(gyroflip::method::scheme_names()));
  sub->add_option("-o,--output", o->output,
                  "write the per-cycle CSV here (default: stdout unless --json)");
  sub->add_option("--drift-window", o->drift_window_s, "moving-mean window for drift_dps (s)")
      ->capture_default_str();
  sub->add_flag("--json", o->json, "print a JSON summary");
  sub->add_flag("--strict", o->strict,
                "refuse a calibration made of a run that failed the stationarity test (exit 2)");
  add_angle_tolerance(sub, o->angle_tolerance_deg);
  sub->parse_complete_callback([dn, cal] {
    if (dn->count() + cal->count() != 1) throw CLI::RequiredError("--delta-n or --calibration");
  });
}

void add_series_options(CLI::App* sub, series_input& in) {
  sub->add_option("file", in.file,
                  "CSV (column by name), NumPy .npy, raw float64 (.f64/.bin/.raw) or HDF5 "
                  "(FILE.h5:/dataset)")
      ->required();
  sub->add_option("--column", in.column,
                  "CSV column to analyse: a name, a number from 1, or several: gx,gy,gz")
      ->capture_default_str();
  sub->add_option("--columns", in.columns,
                  "all-numeric: every numeric column but the time stamps, in one pass")
      ->check(CLI::IsMember({"all-numeric"}));
  sub->add_option("--rate", in.rate_hz, "sample rate (Hz); default: from the CSV time_s column");
  sub->add_option("--dataset", in.dataset, "HDF5 dataset path (or write FILE.h5:/path)");
  sub->add_flag("--ignore-flip", in.ignore_flip,
                "analyse a column that switches with angle_deg (an uncompensated flip recording)");
  sub->add_option("--input", in.input, "what the samples are: rate or angle")
      ->check(CLI::IsMember({"rate", "angle"}))
      ->capture_default_str();
  sub->add_option(
         "--units", in.units,
         "unit of the samples: deg/s, rad/s or deg/h (rate); deg or rad (angle); m/s^2, g, "
         "mg or ug (accelerometer)")
      ->check(CLI::IsMember({"deg/s", "rad/s", "deg/h", "deg", "rad", "m/s^2", "g", "mg", "ug"}))
      ->each([&in](const std::string&) { in.units_given = true; })
      ->capture_default_str();
  sub->add_option("--delimiter", in.delimiter,
                  "CSV field separator: , ; tab or space (default: detected from the first line)")
      ->check(CLI::IsMember({",", ";", "tab", "space", "\t"}));
  sub->add_option("--decimal", in.decimal, "CSV decimal mark: . or ,")
      ->check(CLI::IsMember({".", ","}))
      ->capture_default_str();
  sub->add_flag("--no-header", in.no_header,
                "the CSV has no header line: name columns by number (--column 3)");
  sub->add_option("--time-column", in.time_column,
                  "CSV column of the time stamps (default: time_s)");
  sub->add_option("--time-unit", in.time_unit, "unit of the time stamps: s, ms, us or ns")
      ->check(CLI::IsMember({"s", "ms", "us", "ns"}))
      ->capture_default_str();
  sub->add_option("--gaps", in.gaps,
                  "gaps in the time stamps (a .gfr: lost dwells): error, split (analyse the "
                  "longest gap-free run), or fill (bridge them by linear interpolation, at most "
                  "1 % of the samples; not for a .gfr)")
      ->check(CLI::IsMember({"error", "split", "fill"}))
      ->capture_default_str();
  sub->add_option("--rostopic", in.topic,
                  "ROS bag (.bag, .db3): the sensor_msgs/Imu topic to read (default: the bag's "
                  "only IMU topic; or FILE.bag:/topic); noise --kalibr writes it (default /imu0)");
}

void setup_adev(CLI::App& app, action& chosen) {
  auto* sub =
      app.add_subcommand("adev", "Allan-family deviation with confidence intervals (NIST SP1065)");
  auto o = bind<adev_options>(sub, chosen, run_adev);
  add_series_options(sub, o->in);
  std::vector<std::string> kinds;
  for (const auto& f : analysis::dev_table) kinds.emplace_back(f.name);
  kinds.emplace_back("gradev");
  sub->add_option("--kind", o->kind,
                  analysis::dev_kind_names("|") +
                      "|gradev (gradev: an empty field or nan is a missing sample; a .gfr's "
                      "lost dwells too)")
      ->check(CLI::IsMember(kinds))
      ->capture_default_str();
  sub->add_option("--taus", o->taus, "octave|decade|all or averaging factors like 1,2,10")
      ->capture_default_str();
  sub->add_option("--ci", o->ci,
                  "two-sided confidence level of the bounds, or none (no noise identification, "
                  "no bounds: fastest)")
      ->check(confidence_level(true))
      ->default_str("0.683");
  sub->add_option("--alpha", o->alpha,
                  "the noise type of the intervals and bias correction at every tau, as "
                  "Stable32's setting: 2 white PM, 1 flicker PM, 0 white FM, -1 flicker FM, -2 "
                  "random-walk FM (default: identified at each tau, and beyond half the all-tau "
                  "limit carried from the nearest shorter listed tau, as Stable32)")
      ->check(CLI::Range(-2, 2));
  sub->add_flag(
      "--ci-guard", o->ci_guard,
      "no interval narrower than the noise types at the neighbouring taus allow (default: "
      "the type identified at each tau, as Stable32)");
  sub->add_flag(
      "--bias-correction", o->bias_correction,
      bias_corrected_kinds() + ": Stable32's bias correction by the noise type at each tau");
  sub->add_flag("--codev", o->codev,
                "the Groslambert codeviation (GCODEV) of two columns --column AB,CB: the common "
                "clock B");
  sub->add_flag("--three-cornered-hat", o->three_cornered_hat,
                "clocks A, B, C from three columns --column AB,BC,CA (statistic --kind)");
  sub->add_option("--dynamic", o->dynamic,
                  "WINDOW_S[:STEP_S]: the dynamic deviation (DAVAR), a curve per window of "
                  "WINDOW_S seconds every STEP_S (default WINDOW_S/4); CSV "
                  "start_s,tau_s,dev,ci_lo,ci_hi,edf,n,alpha");
  sub->add_flag("--json", o->json, "print one JSON object");
  sub->add_option("-o,--output", o->output, "write CSV tau_s,dev,ci_lo,ci_hi,edf,n,alpha here");
  sub->add_option("--plot", o->plot,
                  "draw the Allan plot to FILE.png, .svg or .pdf (gnuplot; FILE.gp and its data "
                  "files are written beside it)");
}

void setup_report(CLI::App& app, action& chosen, const std::vector<std::string>& args) {
  auto* sub = app.add_subcommand(
      "report", "A report to send: tables, the paper's figures and the Allan plot in one page");
  auto o = bind<report_options>(sub, chosen, run_report);
  o->command_line = args;
  sub->add_option("files", o->files, "recordings (CSV or .gfr)")->required();
  sub->add_option("-o,--output", o->output, "the report folder DIR (index.html, figures/, ...)")
      ->required();
  sub->add_option("--latitude", o->lat_deg, "latitude (deg) to split dN into Earth and g terms")
      ->check(finite_number());
  sub->add_option("--axis", o->axis, "sensitive axis at 0 deg: north|east|down|up or N,E,D");
  sub->add_option("--calibration", o->calibration,
                  "CAL.json: compensate the files with it (without: calibrate them)");
  sub->add_option("--title", o->title, "the report's title");
  sub->add_option("--sensor", o->sensor,
                  "sensor preset or FILE.toml whose g-sensitivity specification the stationarity "
                  "test checks (default: the recordings' preset)");
  sub->add_option("--pairing", o->pairing, gyroflip::method::scheme_names_joined("|"))
      ->check(CLI::IsMember(gyroflip::method::scheme_names()))
      ->capture_default_str();
  sub->add_option("--expected-rate", o->expected_rate_dps,
                  "the rate the runs were commanded to (deg/s; with --calibration): each run's "
                  "error and scale-factor error against it")
      ->check(finite_number());
}

void setup_reproduce(CLI::App& app, action& chosen, const std::vector<std::string>& args) {
  auto* sub = app.add_subcommand(
      "reproduce", "The paper's experiment on the simulator: Tab. 3/4 and Figs 3-10 side by side");
  auto o = bind<reproduce_options>(sub, chosen, run_reproduce);
  o->command_line = args;
  sub->add_flag("--quick", o->quick, "one campaign, runs a quarter as long (< 60 s)");
  sub->add_option("-o,--output", o->output, "folder for summary.json");
  add_seed(sub, o->seed, "seed of the first campaign");
  sub->add_option("--campaigns", o->campaigns,
                  "campaigns with new seeds, for each figure's ensemble mean and spread "
                  "(default 10; 1 with --quick)");
  sub->add_option("--sensor", o->sensors,
                  "NAME=FILE.toml: put a sensor model to the paper's tests instead of the preset "
                  "NAME (adxrs150 or hz1-90-100a); repeatable")
      ->type_name("NAME=FILE");
}

void setup_noise(CLI::App& app, action& chosen) {
  auto* sub =
      app.add_subcommand("noise", "IEEE 952 noise terms (Q, N, B, K, R) from the Allan deviation");
  auto o = bind<noise_options>(sub, chosen, run_noise);
  add_series_options(sub, o->in);
  sub->add_option("--ci", o->ci, "two-sided confidence level of the terms' intervals")
      ->check(confidence_level(false))
      ->capture_default_str();
  sub->add_flag("--json", o->json, "print one JSON object");
  sub->add_option("--fit-taus", o->fit_taus, "fit the noise model to tau in LO:HI (s) only");
  sub->add_option("-o,--output", o->output,
                  "also write the terms: FILE.json (the --json object) or CSV "
                  "column,term,unit,value,lo,hi,resolved,read_off");
  sub->add_option("--quantity", o->quantity,
                  "what the columns measure: gyro or accel (default: from each column's unit in "
                  "its name, as ax_mps2 or acc_x [m/s^2]; else gyro)")
      ->check(CLI::IsMember({"gyro", "accel"}));
  sub->add_option("--kalibr", o->kalibr,
                  "also write Kalibr's IMU noise YAML (rostopic, update_rate, the accelerometer's "
                  "and the gyro's noise density and random walk in m/s^2 and rad units, the "
                  "largest axis, not inflated): needs gyro and accelerometer columns, in FILE or "
                  "with --kalibr-other");
  sub->add_option("--kalibr-other", o->kalibr_other,
                  "the other sensor's record for --kalibr (accelerometer for a gyro FILE, or "
                  "gyro): every numeric column, read as FILE is, each column's unit from its "
                  "name, else m/s^2 or deg/s");
  sub->add_option("--plot", o->plot,
                  "draw the Allan curves with bounds, fitted term lines and read-off points to "
                  "FILE.png, .svg or .pdf (gnuplot; FILE.gp and its data beside it)");
  sub->add_option("--plot-units", o->plot_units,
                  "the plot's unit: deg/h (default), deg/s or rad/s; for an accelerometer mg "
                  "(default), ug or m/s^2");
  sub->add_option("--title", o->title, "the plot's title (default: Allan deviation of FILE)");
  sub->add_flag("--long-taus", o->long_taus,
                "also OADEV beyond Stable32's m <= (N-1)/4 up to (N-1)/2 (as MATLAB and "
                "allantools): in the plot and JSON long_oadev, never fitted");
}

void setup_plan(CLI::App& app, action& chosen) {
  auto* sub = app.add_subcommand(
      "plan",
      "the dwell and flip period that minimise a run's error for a dead time (docs/PLANNER.md)");
  auto o = bind<plan_options>(sub, chosen, run_plan);
  sub->add_option("--sensor", o->sensor, "the noise of a preset: adxrs150|hz1-90-100a|FILE.toml");
  sub->add_option("--static", o->in.file,
                  "or the noise fitted to a static record (as gyroflip noise reads it: CSV, .npy, "
                  "raw float64, HDF5)");
  sub->add_option("--column", o->in.column, "the static record's column")->capture_default_str();
  sub->add_option("--rate", o->in.rate_hz, "the static record's sample rate (Hz); default: time_s");
  sub->add_option("--units", o->in.units, "unit of the static record: deg/s, rad/s or deg/h")
      ->check(CLI::IsMember({"deg/s", "rad/s", "deg/h"}))
      ->capture_default_str();
  sub->add_option("--dead-time", o->dead_s, "time lost per turn: turn + settle (s)")
      ->required()
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--duration", o->duration_s, "run length (s)")->capture_default_str();
  sub->add_option("--min-dwell", o->min_dwell_s, "shortest dwell considered (s)")
      ->capture_default_str();
  sub->add_option("--max-dwell", o->max_dwell_s,
                  "longest dwell considered (s; default a quarter of the run)");
  sub->add_option("--positions", o->positions,
                  "the table positions A,B,... (deg, 2 to 8; three or more: an indexed run in the "
                  "drift-cancelling sweep, planned for the first harmonic's error)");
  sub->add_option("--order", o->order,
                  "the visiting order planned for, as simulate/record --order: auto (two "
                  "positions A,B,A,B; more: sweep), sweep, cycle, there-and-back")
      ->check(CLI::IsMember({"auto", "sweep", "cycle", "there-and-back"}))
      ->capture_default_str();
  sub->add_flag("--heading", o->heading,
                "plan for north finding: the dwell that minimises the heading's error (positions "
                "default 0,90,180,270; needs --latitude)");
  sub->add_option("--latitude", o->lat_deg, "with --heading: the site's latitude (deg)");
  sub->add_option("--plot", o->plot, "FILE.png|.svg|.pdf: the predicted error against the dwell");
  sub->add_flag("--json", o->json, "print one JSON object");
}

}  // namespace

int run_cli(int argc, char** argv) {
  CLI::App app{"gyroflip: bias-drift compensation of MEMS gyroscopes by 0/180 deg sign reversal"};
  app.name("gyroflip");
  app.set_version_flag("--version", "gyroflip " GYROFLIP_VERSION);
  app.require_subcommand(1);
  action chosen;
  setup_earth(app, chosen);
  setup_simulate(app, chosen);
  setup_emulate(app, chosen);
  setup_record(app, chosen, std::vector<std::string>(argv, argv + argc));
  setup_export(app, chosen);
  setup_sensors(app, chosen);
  setup_calibrate(app, chosen);
  setup_compensate(app, chosen);
  setup_adev(app, chosen);
  setup_noise(app, chosen);
  setup_plan(app, chosen);
  setup_heading(app, chosen);
  setup_report(app, chosen, std::vector<std::string>(argv, argv + argc));
  setup_reproduce(app, chosen, std::vector<std::string>(argv, argv + argc));
  // `gyroflip nosuch --help` must not print the main help and succeed: scripts probe for
  // subcommands that way.
  if (argc > 1 && argv[1][0] != '-') {
    const std::string name = argv[1];
    const auto subs =
        app.get_subcommands([&name](const CLI::App* s) { return s->get_name() == name; });
    if (subs.empty()) {
      std::fprintf(stderr, "gyroflip: error: unknown command '%s' (see gyroflip --help)\n",
                   printable(name, 80).c_str());
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);  // prints the help of the chosen (sub)command, exit 0
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // Usage errors in the documented form (docs/cli.md), exit 2 (not CLI11's 100+). The
    // command's help names every option; the user's words are echoed only as printable text.
    const auto* sub = app.get_subcommands().empty() ? nullptr : app.get_subcommands().front();
    std::fprintf(stderr, "gyroflip: error: %s (see gyroflip%s%s --help)\n",
                 printable(e.what(), 300).c_str(), sub != nullptr ? " " : "",
                 sub != nullptr ? sub->get_name().c_str() : "");
    return 2;
  }
  return chosen ? chosen() : 2;
}

}  // namespace gyroflip::app
