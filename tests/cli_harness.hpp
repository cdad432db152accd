// Running the `chatter` binary from a test: a fresh scratch directory per
// test, the command's exit code, stdout and stderr. Shared by the tests that
// drive the CLI end to end (test_cli, test_cli_fit, test_cli_simulate).
//
// CHATTER_CLI (the binary's path) is defined by chatter_add_test in
// tests/CMakeLists.txt.
#pragma once

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace chatter::test {

namespace fs = std::filesystem;

/// `s` as one word for /bin/sh (single quotes, embedded quotes escaped).
inline std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += "'\\''";
    else out += c;
  }
  return out + "'";
}

/// The whole file as bytes ("" if it cannot be read).
inline std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream os;
  os << f.rdbuf();
  return os.str();
}

inline bool contains(const std::string& hay, const std::string& needle) {
  return hay.find(needle) != std::string::npos;
}

/// The user's opt-in to a commented `[uncertainty]` table written by
/// `chatter fit` / `chatter coefficients`: the '#' removed in front of
/// `[uncertainty]` and of every `key = value` line right after it.
inline std::string uncomment_uncertainty(const std::string& toml) {
  std::istringstream in(toml);
  std::string out;
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    if (line == "#[uncertainty]") inside = true;
    else if (inside && !(line.size() > 1 && line[0] == '#' && std::islower(static_cast<unsigned char>(line[1]))))
      inside = false;
    out += (inside ? line.substr(1) : line) + "\n";
  }
  return out;
}

struct RunResult {
  int exit_code = -1;  ///< -1 if the command did not exit normally
  std::string out, err;
};

/// A fixture with a fresh directory per test (removed afterwards) and run(),
/// which executes `chatter ARGS...` with stdin from /dev/null.
class CliFixture : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = make_dir(); }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  /// temp/chatter_test_<suite>_<test>_<pid>, empty.
  static fs::path make_dir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string("chatter_test_") + info->test_suite_name() + "_" + info->name() + "_" +
                       std::to_string(::getpid());
    for (char& c : name)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') c = '_';
    const fs::path d = fs::temp_directory_path() / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
  }

  /// Runs `chatter ARGS...`, capturing stdout and stderr through files in dir_.
  RunResult run(const std::vector<std::string>& args) {
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    std::string cmd = shell_quote(CHATTER_CLI);
    // Appended piecewise: `"literal" + std::string` trips a GCC 12 -Wrestrict false positive.
    for (const auto& a : args) cmd.append(" ").append(shell_quote(a));
    cmd.append(" >").append(shell_quote(out.string()));
    cmd.append(" 2>").append(shell_quote(err.string()));
    cmd.append(" </dev/null");
    const int status = std::system(cmd.c_str());
    RunResult r;
    r.exit_code = (status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    fs::remove(out);
    fs::remove(err);
    return r;
  }

  fs::path path(const std::string& name) const { return dir_ / name; }

  fs::path dir_;
};

}  // namespace chatter::test
