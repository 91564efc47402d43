#include "support/run_cli.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "support/temp_dir.hpp"

extern char** environ;

namespace gyroflip::test {

namespace {

int exit_status(int st) {
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

// Starts argv_s[0] (looked up on PATH) with its arguments, stdin from /dev/null, stdout and
// stderr to the given files.
pid_t spawn_program(std::vector<std::string> argv_s, const char* out_path, const char* err_path) {
  std::vector<char*> argv;
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 1, out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 2, err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) throw std::runtime_error("posix_spawn failed");
  return pid;
}

// Starts GYROFLIP_EXE with `args`.
pid_t spawn(const std::vector<std::string>& args, const char* out_path, const char* err_path) {
  std::vector<std::string> argv_s{GYROFLIP_EXE};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  return spawn_program(std::move(argv_s), out_path, err_path);
}

cli_result wait_result(pid_t pid, const std::string& out_path, const std::string& err_path) {
  int st = 0;
  struct rusage ru {};
  wait4(pid, &st, 0, &ru);
  cli_result r;
  r.max_rss_kb = ru.ru_maxrss;
  r.exit_code = exit_status(st);
  r.out = read_text(out_path);
  r.err = read_text(err_path);
  return r;
}

}  // namespace

cli_result run_cli(const std::vector<std::string>& args) {
  temp_dir tmp;
  const std::string out_path = tmp.file("stdout");
  const std::string err_path = tmp.file("stderr");
  return wait_result(spawn(args, out_path.c_str(), err_path.c_str()), out_path, err_path);
}

cli_result run_program(const std::vector<std::string>& argv) {
  temp_dir tmp;
  const std::string out_path = tmp.file("stdout");
  const std::string err_path = tmp.file("stderr");
  return wait_result(spawn_program(argv, out_path.c_str(), err_path.c_str()), out_path, err_path);
}

int spawn_cli(const std::vector<std::string>& args) {
  return spawn(args, "/dev/null", "/dev/null");
}

int wait_cli(int pid) {
  int st = 0;
  waitpid(pid, &st, 0);
  return exit_status(st);
}

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

std::string read_page(const std::string& path) {
  std::string html = read_text(path);
  for (const std::string_view tag : {"<span class=\"nw\">", "<span class=\"brk\">", "</span>"})
    for (auto at = html.find(tag); at != std::string::npos; at = html.find(tag, at))
      html.erase(at, tag.size());
  return html;
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
}

bool exists(const std::string& path) {
  return std::filesystem::exists(path);
}

}  // namespace gyroflip::test
