/// \file
/// \brief The table's positions (issue 33): one type {index, angle_deg, steps} from the device's
/// CONFIGURE (its angle table, docs/PROTOCOL.md) through the rig's settings, a recording's rows
/// (a position index, -1 while the table turns) and the method to the report.
///
/// A row or a dwell names its position by index; the angle is the table's. A demodulator decides
/// what each position means to it (the 0/180 pairings: method/flip_pair.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyroflip/core/result.hpp"

namespace gyroflip {

/// The position index of a row taken while the table turns (no position).
inline constexpr int table_moving = -1;

/// One position of the table.
struct table_position {
  /// A position whose motor steps are unknown (a CSV recording, an array of angles).
  static constexpr std::int32_t unknown_steps = std::numeric_limits<std::int32_t>::min();
  int index = 0;                       ///< its place in the table, 0-based (a DWELL's `position`)
  double angle_deg = 0.0;              ///< the table angle it stands for, [0, 360)
  std::int32_t steps = unknown_steps;  ///< the flip motor's steps from home, if known
  bool operator==(const table_position&) const = default;
};

/// The table's positions, indexed 0..size()-1: 1 to max_positions distinct angles in [0, 360).
/// (One position is an unflipped recording; the device's table holds 2 to 8.)
class position_table {
 public:
  /// Positions a table holds at most (the device's max_positions, docs/PROTOCOL.md).
  static constexpr std::size_t max_positions = 8;

  /// An empty table (no positions: read from the rows, see io::recording_reader).
  position_table() = default;
  /// The paper's table: index 0 at 0 deg, index 1 at 180 deg (the device's default CONFIGURE).
  [[nodiscard]] static position_table pair_0_180();
  /// A table of these angles in this order (`steps` empty, or one per angle). Error (a usage
  /// error naming the angle) unless 1..max_positions finite angles in [0, 360), distinct.
  [[nodiscard]] static result<position_table> of_angles(std::span<const double> angles_deg,
                                                        std::span<const std::int32_t> steps = {});
  /// The table of a device's angle table (CONFIGURE's pos_cdeg, rig::rig_config's positions),
  /// which is a visiting order: it may name an angle twice (0,180,0,180; only consecutive
  /// positions must differ). Each angle once, in the order first visited, with the steps of its
  /// first visit; a dwell's position is found by its angle (index_of). Error as of_angles.
  [[nodiscard]] static result<position_table> of_visits(std::span<const double> angles_deg,
                                                        std::span<const std::int32_t> steps = {});

  [[nodiscard]] std::size_t size() const noexcept { return positions_.size(); }
  [[nodiscard]] bool empty() const noexcept { return positions_.empty(); }
  [[nodiscard]] std::span<const table_position> positions() const noexcept { return positions_; }
  /// Whether `index` names a position of the table.
  [[nodiscard]] bool holds(int index) const noexcept {
    return index >= 0 && static_cast<std::size_t>(index) < positions_.size();
  }
  /// Position `index`'s angle (deg); `index` must be held.
  [[nodiscard]] double angle_deg(int index) const {
    return positions_.at(static_cast<std::size_t>(index)).angle_deg;
  }
  /// The index of the position within `tol_deg` of `angle_deg` on the circle (359.9 is 0.1 deg
  /// from 0), the nearest when several are; nullopt when none is.
  [[nodiscard]] std::optional<int> index_of(double angle_deg, double tol_deg = 0.0) const noexcept;
  /// The angles as a list: for messages `0, 90, 180 and 270` (`words`), for a `# positions_deg:`
  /// line `0,90,180,270`.
  [[nodiscard]] std::string describe(bool words = true) const;

  bool operator==(const position_table&) const = default;

 private:
  std::vector<table_position> positions_;
};

/// The angle between two table angles on the circle (deg), in [0, 180].
[[nodiscard]] double angle_between_deg(double a_deg, double b_deg) noexcept;

}  // namespace gyroflip
