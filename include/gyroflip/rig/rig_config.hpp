/// \file
/// \brief The rig's settings: one type for the simulator, the emulator, the recorder and the
/// device's CONFIGURE, with one validation.
///
/// Every field is a setting of the real rig (docs/PROTOCOL.md, CONFIGURE): how many conversions a
/// dwell averages, where the table stands (an angle table of 2 to 8 positions, each a whole
/// number of the flip motor's full steps), how the stepper ramps, how the AD7739 converts and
/// what the firmware sends. `check` applies the device's own rules (protocol::check_configure:
/// ranges, distinct positions within a revolution, on-board compensation only for a 180-deg
/// pair, the worst case within the link) with a message per field; `to_configure` is the
/// CONFIGURE payload, `from_configure` its inverse. The simulator reads the same value
/// (simulation_config::rig), so a simulated run and a recorded one cannot disagree on a setting
/// (the simulator models no temperature conversions: docs/SIMULATOR.md).
#pragma once

#include <vector>

#include "firmware/protocol/messages.hpp"
#include "gyroflip/core/positions.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/rig/schedule.hpp"
#include "gyroflip/rig/turntable.hpp"

namespace gyroflip::rig {

struct rig_config {
  int n_avg = 256;  ///< gyro conversions per dwell (paper: 256), 1..65535
  int n_temp = 4;   ///< temperature conversions per dwell, after the gyro's, 0..64
  double settle_s =
      0.08;  ///< wait after a turn before the first conversion, 0..65.535 s (ms steps)
  /// The angle table (deg, [0, 360)): position i of a DWELL stands at positions_deg[i]. Each a
  /// whole number of full steps from home; 2..8, consecutive ones distinct. Default: A = 0, B =
  /// 180.
  std::vector<double> positions_deg{0.0, 180.0};
  int steps_per_rev = 200;       ///< full steps per turn of the table, 4..32767
  int start_rate_sps = 200;      ///< first step rate of the ramp (pull-in), 1..max_rate_sps
  int max_rate_sps = 400;        ///< top step rate, 1..5000
  int accel_sps2 = 2000;         ///< ramp, 1..65535 steps/s^2
  int filter_word = 94;          ///< AD7739 FW, 2..127 (~2 ms with chopping)
  bool chop = true;              ///< AD7739 chopping
  bool one_way = false;          ///< turn always the same way (a rotary joint) instead of back
  bool home = false;             ///< find the home switch before the first cycle
  bool hold_coils = false;       ///< keep the coils energised during dwells (heats the table)
  bool raw = false;              ///< send every gyro conversion (RAW)
  bool compensate = false;       ///< send COMPENSATED per cycle (the 180-deg pair only)
  double status_period_s = 1.0;  ///< STATUS every this many s, 0 (on request only)..60
  int flip_motor = 0;            ///< 0: low nibble of the stepper port, 1: high nibble
  protocol::other_motor other_motor = protocol::other_motor::off;
  int gyro_channel = 0;  ///< AD7739 channel of the gyro, 0..3
  int temp_channel = 1;  ///< AD7739 channel of the temperature output, 0..3, not the gyro's

  /// The device's rules, each broken one named (parameter error naming the field). `mclk_hz`:
  /// the AD7739's clock, for the conversion time in the link budget.
  [[nodiscard]] status check(double mclk_hz = 6.144e6) const;
  /// The CONFIGURE payload (after check: every value fits its field).
  [[nodiscard]] protocol::configure_msg to_configure() const;
  /// The settings a device runs with (INFO, a CONFIGURE record of a .gfr), checked.
  [[nodiscard]] static result<rig_config> from_configure(const protocol::configure_msg& m);

  /// The stepper as the turntable model takes it.
  [[nodiscard]] stepper_params stepper() const;
  /// The simulator's schedule; `flip` false keeps the table at A. Two distinct positions: the
  /// cycle A, B (unless `order` is sweep: A, B, B, A); an angle table naming an angle twice is
  /// a visiting order and is visited as written; three or more distinct positions are swept
  /// (schedule.hpp, sweep_order) unless `order` is cycle.
  [[nodiscard]] schedule_params schedule(bool flip,
                                         visit_order order = visit_order::automatic) const;
  /// Position i's step from home (angle / step angle, rounded).
  [[nodiscard]] int position_steps(std::size_t i) const;
  /// The angle table as the position table the recordings' rows name (core/positions.hpp:
  /// position_table::of_visits, with each position's steps); empty if it is not valid (check).
  [[nodiscard]] position_table table() const;
};

/// How the device visits distinct table positions (`record --order`, issue 33 item 2). The
/// device steps through its angle table 0, 1, ..., n-1, 0, ... (docs/PROTOCOL.md, CONFIGURE),
/// turning before every dwell (consecutive entries differ) and holding at most
/// protocol::max_positions entries, so a visiting order is written as the table itself (an angle
/// named twice; a DWELL's position is its entry, the recordings map it to the position by its
/// angle: position_table::of_visits).
enum class device_order {
  automatic,  ///< two positions: as given (A, B); more: there_and_back where it fits, else cycle
  cycle,      ///< the positions as given, over and over
  there_and_back,  ///< 0, 1, ..., N-1, N-2, ..., 1 (2N - 2 entries; N <= 5, not one-way)
};

/// The device's angle table that visits the distinct `positions_deg` in `order`. there_and_back:
/// forwards then back without a second dwell at either end (the device dwells once per turn, so
/// the simulator's sweep, each end twice, is not a table it can hold): each inner position is
/// visited twice a period, the ends once; the visits of each position are centred on the same
/// time within a period, ends included across its boundary, so a bias linear in time enters
/// every position's mean alike over whole periods closed by a dwell at the first position.
/// automatic takes it for three to five positions without one-way turns (the turns go back),
/// else cycle. Errors (usage): there_and_back with one-way turns or more than five positions
/// (2N - 2 > protocol::max_positions); a table that already names an angle twice (a visiting
/// order: given with cycle or automatic, it is taken as written).
[[nodiscard]] result<std::vector<double>> device_visits(const std::vector<double>& positions_deg,
                                                        device_order order, bool one_way);

}  // namespace gyroflip::rig
