// A user's program against the installed library: OADEV of NIST SP1065's NBS14 set (p. 107,
// 91.22945 at tau = 1 s and 85.95287 at 2 s), a built-in sensor preset (toml++ behind it) and
// a calibration of a simulated run (rig, method, io). Exit 0 when every figure is as expected.
#include <cmath>
#include <cstdio>
#include <vector>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/cycles.hpp"
#include "gyroflip/rig/simulator.hpp"
#include "gyroflip/sensor/presets.hpp"

int main() {
  using namespace gyroflip;
  const std::vector<double> y{892, 809, 823, 798, 671, 644, 883, 903, 677};
  const auto curve = analysis::deviation(analysis::dev_kind::oadev, y, analysis::input_kind::rate,
                                         1.0, *analysis::parse_tau_spec("1,2"));
  if (!curve || curve->size() != 2) return 1;
  const double d1 = (*curve)[0].dev, d2 = (*curve)[1].dev;
  std::printf("oadev %.7g %.7g\n", d1, d2);
  if (std::abs(d1 / 91.22945 - 1) > 1e-6 || std::abs(d2 / 85.95287 - 1) > 1e-6) return 1;

  const auto preset = sensor::load_preset("hz1-90-100a");
  if (!preset) return 1;
  rig::simulation_config c;
  c.sensor = preset->params;
  c.duration_s = 120.0;
  auto sim = rig::simulator::make(c);
  if (!sim) return 1;
  rig::sample_block block(1u << 14, false);
  rig::dwell_averager avg(c.rig.n_avg);
  std::vector<rig::dwell_row> rows;
  while (sim->fill(block) > 0) avg.add(block, rows);
  std::vector<method::row> rec;
  const position_table table = c.rig.table();
  for (const auto& r : rows)
    rec.push_back({r.time_s, table.index_of(r.angle_deg).value_or(table_moving), r.rate_dps,
                   r.temp_c, static_cast<std::uint32_t>(r.n_avg)});
  const auto cycles = method::cycles_of_rows("simulated", rec, method::pairing::abba);
  if (!cycles) return 1;
  const auto cal = method::calibrate(cycles->cycles);
  if (!cal) return 1;
  std::printf("dN %.6f deg/s from %zu cycles\n", cal->delta_n_dps, cal->cycles);
  return std::abs(cal->delta_n_dps) > 0.0 ? 0 : 1;
}
