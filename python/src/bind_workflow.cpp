/// \file
/// \brief The experiments for Python, the CLI's workflow calls (workflow/*.hpp): `_report` (the
/// report folder) and `_reproduce` (the paper's experiment). Results are the CLI's JSON objects
/// (its summary.json), parsed.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>

#include "common.hpp"
#include "gyroflip/workflow/report.hpp"
#include "gyroflip/workflow/reproduce.hpp"

namespace gyroflip::python {

namespace {

py::dict report(const std::vector<std::string>& files, const std::string& output,
                std::optional<double> lat_deg, const std::optional<std::string>& axis,
                const std::string& calibration, const std::string& title,
                const std::string& pairing, std::optional<double> expected_rate_dps,
                const std::string& command, const std::string& next_step) {
  workflow::report_request req;
  req.next_step = next_step;
  req.files = files;
  req.output = output;
  req.geometry = geometry_of(lat_deg, axis);
  req.calibration = calibration;
  req.title = title;
  const auto p = method::parse_pairing(pairing);
  if (!p) throw py::value_error("pairing must be 'abba' or 'simple' (got '" + pairing + "')");
  req.pairing = *p;
  req.expected_rate_dps = expected_rate_dps;
  req.command = command;
  req.made_by = "gyroflip.report (Python)";
  auto run =
      without_gil([&](const progress_fn& listen) { return workflow::make_report(req, listen); });
  const auto res = take(std::move(run));
  return json_loads(res.summary_json);  // its "warnings" are the result's
}

py::dict reproduce(bool quick, std::uint64_t seed, std::optional<std::size_t> campaigns,
                   const std::string& output,
                   const std::vector<std::pair<std::string, std::string>>& sensors,
                   const std::string& command) {
  workflow::reproduce_request req;
  req.quick = quick;
  req.seed = seed;
  req.campaigns = campaigns;
  req.output = output;
  for (const auto& [name, path] : sensors) req.sensor_files.push_back({name, path});
  req.command = command;
  req.made_by = "gyroflip.reproduce (Python)";
  auto run =
      without_gil([&](const progress_fn& listen) { return workflow::reproduce(req, listen); });
  const auto res = take(std::move(run));
  py::dict d = json_loads(res.summary_json);
  d["text"] = res.text;
  return d;
}

}  // namespace

void bind_workflow(py::module_& m) {
  m.def("_report", &report, py::arg("files"), py::arg("output"), py::arg("latitude"),
        py::arg("axis"), py::arg("calibration"), py::arg("title"), py::arg("pairing"),
        py::arg("expected_rate"), py::arg("command"), py::arg("next_step"));
  m.def("_reproduce", &reproduce, py::arg("quick"), py::arg("seed"), py::arg("campaigns"),
        py::arg("output"), py::arg("sensors"), py::arg("command"));
}

}  // namespace gyroflip::python
