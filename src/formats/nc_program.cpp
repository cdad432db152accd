// An NC program through LinuxCNC's RS274/NGC interpreter
// (chatter/io/nc_program.hpp, docs/program.md "Reading the program").
#include "chatter/io/nc_program.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "chatter/error.hpp"

extern char** environ;

namespace chatter {
namespace fs = std::filesystem;
namespace {

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

// A temporary folder removed on every path out.
struct TempDir {
  fs::path path;
  TempDir() {
    std::string templ = (fs::temp_directory_path() / "chatter-nc-XXXXXX").string();
    if (!::mkdtemp(templ.data())) throw InputError("cannot create a temporary folder for the interpreter's files");
    path = templ;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

// Runs argv with stdin /dev/null and stdout, stderr to files, our
// environment but HOME = `home`; returns the exit status (-1 when killed by
// the timeout). LinuxCNC's tool data lives in a memory-mapped $HOME/.tool.mmap:
// two interpreters sharing one HOME (threads, parallel tests, a post-processor
// checking programs side by side) truncate each other's map and die of
// SIGBUS, and the user's HOME would keep the file. A private HOME each.
int run_process(const std::vector<std::string>& args, const fs::path& out, const fs::path& err, double timeout_s,
                const fs::path& home) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const std::string home_entry = "HOME=" + home.string();
  std::vector<char*> env;
  for (char** e = environ; e && *e; ++e)
    if (std::strncmp(*e, "HOME=", 5) != 0) env.push_back(*e);
  env.push_back(const_cast<char*>(home_entry.c_str()));
  env.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  pid_t pid = 0;
  const int rc = ::posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), env.data());
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw InputError(args[0] + ": cannot run the G-code interpreter (" + std::strerror(rc) + ")");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  int status = 0;
  for (auto wait = std::chrono::microseconds(200);;) {
    const pid_t w = ::waitpid(pid, &status, WNOHANG);
    if (w == pid) break;
    if (w < 0 && errno != EINTR) throw InputError(args[0] + ": lost the interpreter's process");
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(wait);
    wait = std::min(wait * 2, std::chrono::microseconds(20000));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

std::string trim(std::string s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

// The line number of an interpreter message's echoed block ("N12 G41 ...").
int echoed_line(const std::string& block) {
  std::string s = trim(block);
  if (!s.empty() && s[0] == '/') s = trim(s.substr(1));
  if (s.size() < 2 || (s[0] != 'N' && s[0] != 'n')) return 0;
  return std::atoi(s.c_str() + 1);
}

}  // namespace

std::string number_program_lines(const std::string& program) {
  std::ostringstream out;
  std::istringstream in(program);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::string body = line;
    const auto first = body.find_first_not_of(" \t");
    if (first == std::string::npos || body[first] == '%') {
      out << line << "\n";
      continue;
    }
    body = body.substr(first);
    std::string prefix;
    if (body[0] == '/') {  // block delete comes before the N word
      prefix = "/";
      body = trim(body.substr(1));
    }
    if (!body.empty() && (body[0] == 'N' || body[0] == 'n')) {  // an N word of its own: replaced
      std::size_t k = 1;
      while (k < body.size() && (std::isdigit(static_cast<unsigned char>(body[k])) || body[k] == ' ')) ++k;
      body = body.substr(k);
    }
    out << prefix << "N" << number << " " << body << "\n";
  }
  return out.str();
}

fs::path nc_interpreter(const NcReadOptions& options) {
  if (!options.interpreter.empty()) return options.interpreter;
  if (const char* env = std::getenv("CHATTER_RS274"); env && *env) return env;
  return "/usr/bin/rs274";
}

Toolpath read_nc_program(const fs::path& file, const NcReadOptions& options) {
  std::ifstream probe(file, std::ios::binary);
  if (!probe) throw InputError(file.string() + ": cannot read the NC program (" + std::strerror(errno) + ")");
  const std::string text = read_all(file);
  const fs::path rs274 = nc_interpreter(options);
  if (::access(rs274.c_str(), X_OK) != 0)
    throw InputError(rs274.string() +
                     ": the RS274/NGC interpreter was not found (install LinuxCNC's: apt-get install "
                     "--no-install-recommends linuxcnc-uspace; scripts/setup.sh does), or set CHATTER_RS274");
  TempDir dir;
  const fs::path program = dir.path / "program.ngc", table = dir.path / "tools.tbl";
  {
    std::ofstream p(program, std::ios::binary);
    p << number_program_lines(text);
    // The interpreter stops at M2/M30 or at the end of the file; a last
    // block without a newline is still a block.
    std::ofstream t(table, std::ios::binary);
    for (const auto& [number, diameter_mm] : options.tool_diameters_mm) {
      // The standalone interpreter reads the table in inches.
      char row[96];
      std::snprintf(row, sizeof row, "T%d P%d D%.9f ;\n", number, number, diameter_mm / 25.4);
      t << row;
    }
    if (!p || !t) throw InputError(dir.path.string() + ": cannot write the interpreter's files");
  }
  const fs::path out = dir.path / "canon.txt", err = dir.path / "errors.txt";
  const int status =
      run_process({rs274.string(), "-t", table.string(), "-g", program.string()}, out, err, options.timeout_s, dir.path);
  if (status < 0)
    throw InputError(file.string() + ": the interpreter ran longer than " + std::to_string(int(options.timeout_s)) +
                     " s (an endless loop?)");
  // The interpreter writes its error as the message, then the offending
  // block (with our N word), after the word "executing".
  std::vector<std::string> messages;
  {
    std::istringstream es(read_all(err));
    std::string l;
    while (std::getline(es, l))
      if (trim(l) != "executing" && !trim(l).empty()) messages.push_back(trim(l));
  }
  if (status != 0 || !messages.empty()) {
    int line = 0;
    std::string message;
    for (const std::string& m : messages) {
      if (const int n = echoed_line(m); n > 0) {
        line = n;
        break;
      }
      message += (message.empty() ? "" : "; ") + m;
    }
    if (message.empty())
      message = status > 128 ? "the interpreter was killed by signal " + std::to_string(status - 128) + " (" +
                                   strsignal(status - 128) + ")"
                             : "the interpreter stopped with status " + std::to_string(status);
    throw InputError(file.string() + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + message);
  }
  Toolpath path = parse_canon_log(read_all(out), file.string());
  return path;
}

}  // namespace chatter
