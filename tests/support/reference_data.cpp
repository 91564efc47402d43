#include "support/reference_data.hpp"

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace gyroflip::test {

std::vector<double> read_values(std::istream& in) {
  std::vector<double> v;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    double x = 0.0;
    if (s >> x) v.push_back(x);
  }
  return v;
}

std::vector<double> read_values(const std::string& path) {
  std::ifstream f(path);
  return read_values(f);
}

std::vector<stable32_row> read_stable32_table(const std::string& path) {
  std::ifstream f(path);
  std::vector<stable32_row> rows;
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    stable32_row r;
    double tau = 0.0;
    if (s >> r.af >> tau >> r.n >> r.alpha >> r.lo >> r.sigma >> r.hi) rows.push_back(r);
  }
  return rows;
}

std::string gps_dir() {
  return std::string(GYROFLIP_SHARED_DIR) + "/reference/allan/gps/";
}

std::optional<std::vector<double>> gps_phase() {
  std::FILE* p =
      ::popen(("gzip -dc '" + gps_dir() + "gps_1pps_phase_data.txt.gz' 2>/dev/null").c_str(), "r");
  if (p == nullptr) return std::nullopt;
  std::string text;
  char buf[1 << 16];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) text.append(buf, n);
  ::pclose(p);
  if (text.empty()) return std::nullopt;
  std::istringstream in(text);
  return read_values(in);
}

std::vector<double> nbs14_1000() {
  std::vector<double> y;
  std::uint64_t n = 1234567890;
  for (int i = 0; i < 1000; ++i) {
    y.push_back(static_cast<double>(n) / 2147483647.0);
    n = (16807 * n) % 2147483647;
  }
  return y;
}

}  // namespace gyroflip::test
