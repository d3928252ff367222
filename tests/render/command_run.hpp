// Running the sphray command as a process for the command's tests, and a scratch directory per
// test for the files it reads and writes.
#pragma once

#include <gtest/gtest.h>
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <string>

namespace sphray::test {

struct CommandResult {
  int status;       // the exit status, -1 if the process did not exit normally
  std::string out;  // stdout and stderr together
};

/// `<program> <args>` through the shell (args may quote and redirect).
inline CommandResult run_program(const std::string& program, const std::string& args) {
  const std::string command = program + " " + args + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return {-1, "popen failed"};
  std::string out;
  char buffer[4096];
  while (std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe))
    out.append(buffer, n);
  const int raw = ::pclose(pipe);
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, out};
}

/// `sphray <args>` through the shell (args may quote and redirect).
inline CommandResult run_sphray(const std::string& args) {
  return run_program(SPHRAY_EXE, args);
}

/// `sphray <args>` with a terminal (a pseudo-terminal) for its stdin, stdout and stderr, which
/// it reads as a user would see them, control characters included.
inline CommandResult run_sphray_on_terminal(const std::string& args) {
  int terminal = -1;
  const pid_t child = ::forkpty(&terminal, nullptr, nullptr, nullptr);
  if (child < 0) return {-1, "forkpty failed"};
  if (child == 0) {
    const std::string command = std::string(SPHRAY_EXE) + " " + args;
    ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  std::string out;
  char buffer[4096];
  for (;;) {  // read() fails with EIO once the child has exited and the terminal is closed
    const ssize_t n = ::read(terminal, buffer, sizeof buffer);
    if (n > 0) {
      out.append(buffer, static_cast<std::size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  ::close(terminal);
  int raw = 0;
  ::waitpid(child, &raw, 0);
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, out};
}

/// A fixture whose test gets an empty directory of its own, named after the test, removed after.
class ScratchDirTest : public ::testing::Test {
 protected:
  explicit ScratchDirTest(std::string prefix) : prefix_(std::move(prefix)) {}
  void SetUp() override {
    // The process id too: two build trees' tests may run at once and share /tmp.
    dir_ = std::filesystem::temp_directory_path() /
           (prefix_ + ::testing::UnitTest::GetInstance()->current_test_info()->name() + "-" +
            std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::filesystem::path dir_;

 private:
  std::string prefix_;
};

}  // namespace sphray::test
