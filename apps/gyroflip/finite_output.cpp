/// \file
/// \brief Printing through the finite-output gate (see finite_output.hpp).
#include "finite_output.hpp"

#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "gyroflip/io/schema.hpp"

namespace gyroflip::app {

nlohmann::json with_schema(std::string_view what, int n, nlohmann::json j) {
  auto out = io::schema_object(what, n);
  out.update(std::move(j));
  return out;
}

status print_json(const nlohmann::json& j) {
  auto text = finite_dump(j, "<stdout>");
  if (!text) return text.err();
  *text += '\n';
  std::fwrite(text->data(), 1, text->size(), stdout);
  return ok();
}

status print_checked(std::string_view text, std::string_view what) {
  if (auto s = check_finite(text, what); !s) return s;
  std::fwrite(text.data(), 1, text.size(), stdout);
  return ok();
}

}  // namespace gyroflip::app
