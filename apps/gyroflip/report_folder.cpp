/// \file
/// \brief Report folders built aside and renamed into place (report_folder.hpp).
#include "report_folder.hpp"

#include <stdlib.h>

#include <filesystem>
#include <system_error>

#include "gyroflip/core/error.hpp"

namespace gyroflip::app {

namespace fs = std::filesystem;

result<std::string> staging_folder(const std::string& out) {
  const fs::path target = fs::absolute(out);
  std::error_code ec;
  if (fs::exists(target, ec)) {
    const bool previous = fs::exists(target / "index.html") && fs::exists(target / "summary.json");
    if (!fs::is_directory(target) || (!fs::is_empty(target) && !previous))
      return io_error(out, "exists and is not a gyroflip report folder: give a new folder");
  }
  std::string name = ".";
  name.append(target.filename().string()).append(".tmp-XXXXXX");
  std::string tmpl = (target.parent_path() / name).string();
  if (::mkdtemp(tmpl.data()) == nullptr) return io_error(out, "cannot create a folder beside it");
  fs::create_directory(fs::path(tmpl) / "figures", ec);
  if (ec) return io_error(out, ec.message());
  return tmpl;
}

status publish(const std::string& staging, const std::string& out) {
  const fs::path target = fs::absolute(out);
  std::error_code ec;
  fs::path old;
  if (fs::exists(target, ec)) {
    std::string name = ".";
    name.append(target.filename().string()).append(".old");
    old = target.parent_path() / name;
    fs::remove_all(old, ec);
    fs::rename(target, old, ec);
    if (ec) return io_error(out, ec.message());
  }
  fs::rename(staging, target, ec);
  if (ec) return io_error(out, ec.message());
  if (!old.empty()) fs::remove_all(old, ec);
  return ok();
}

}  // namespace gyroflip::app
