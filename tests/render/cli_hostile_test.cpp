// Issue 20: the sphray command on a hostile host, run as a child process set up as a hostile
// caller would (limits, ignored signals, closed streams, another user, signals mid-render).
// Each test names the issue's case it covers; docs/robustness.md lists them.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/capability.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <stb/stb_image.h>

#include "test_files.hpp"

// Each ChildSetup names only what it changes (designated initializers); the rest defaults.
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

namespace {

namespace fs = std::filesystem;

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitized = true;  // the sanitizers reserve terabytes of address space
#else
constexpr bool kSanitized = false;
#endif

// How the child is set up before sphray runs in it.
struct ChildSetup {
  std::vector<std::string> args;
  std::vector<std::string> env;  // NAME=value, added to this process's environment
  std::vector<std::pair<int, rlim_t>> limits;
  std::vector<int> ignored_signals;
  bool close_stderr = false;
  std::string stdout_path;  // stdout opened on this path (e.g. /dev/full), else the pipe
  std::string stdin_text;   // given on stdin through a pipe
  // Root keeps its user but loses the capabilities that let it read and search any folder, so
  // that permissions apply to it as to anyone (the binary stays where it is: reachable).
  bool without_dac_override = false;
};

struct Outcome {
  int exit = -1;    // the exit status, or -1 if a signal ended it
  int signal = 0;   // the signal that ended it
  std::string out;  // stdout (unless redirected) and stderr (unless closed) together
};

class Child {
 public:
  explicit Child(const ChildSetup& setup) {
    int out[2], in[2];
    if (::pipe2(out, O_CLOEXEC) != 0 || ::pipe2(in, O_CLOEXEC) != 0) std::abort();
    // Everything the child needs is prepared here: after fork only async-signal-safe calls.
    std::vector<std::string> args{SPHRAY_EXE};
    args.insert(args.end(), setup.args.begin(), setup.args.end());
    std::vector<char*> argv;
    for (std::string& a : args)
      argv.push_back(a.data());
    argv.push_back(nullptr);
    std::vector<std::string> env;
    for (char** e = environ; *e != nullptr; ++e)
      env.emplace_back(*e);
    env.insert(env.end(), setup.env.begin(), setup.env.end());
    std::vector<char*> envp;
    for (std::string& e : env)
      envp.push_back(e.data());
    envp.push_back(nullptr);
    pid_ = ::fork();
    if (pid_ < 0) std::abort();
    if (pid_ == 0) {
      ::dup2(in[0], STDIN_FILENO);
      if (!setup.stdout_path.empty()) {
        int fd = ::open(setup.stdout_path.c_str(), O_WRONLY);
        ::dup2(fd, STDOUT_FILENO);
      } else {
        ::dup2(out[1], STDOUT_FILENO);
      }
      ::dup2(out[1], STDERR_FILENO);
      if (setup.close_stderr) ::close(STDERR_FILENO);
      for (int s : setup.ignored_signals)
        ::signal(s, SIG_IGN);
      for (auto [resource, value] : setup.limits) {
        rlimit limit{value, value};
        if (::setrlimit(resource, &limit) != 0) ::_exit(121);
      }
      if (setup.without_dac_override && ::geteuid() == 0 &&
          (::prctl(PR_CAPBSET_DROP, CAP_DAC_OVERRIDE) != 0 ||
           ::prctl(PR_CAPBSET_DROP, CAP_DAC_READ_SEARCH) != 0))
        ::_exit(122);
      ::execve(argv[0], argv.data(), envp.data());
      ::_exit(127);
    }
    ::close(out[1]);
    ::close(in[0]);
    out_ = out[0];
    std::size_t written = 0;
    while (written < setup.stdin_text.size()) {
      ssize_t n =
          ::write(in[1], setup.stdin_text.data() + written, setup.stdin_text.size() - written);
      if (n <= 0) break;
      written += static_cast<std::size_t>(n);
    }
    ::close(in[1]);
  }
  ~Child() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      wait();
    }
    if (out_ >= 0) ::close(out_);
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  void signal(int s) const { ::kill(pid_, s); }

  Outcome wait() {
    Outcome o;
    char buffer[4096];
    for (ssize_t n; (n = ::read(out_, buffer, sizeof buffer)) > 0;)
      o.out.append(buffer, static_cast<std::size_t>(n));
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    if (WIFEXITED(status)) o.exit = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) o.signal = WTERMSIG(status);
    return o;
  }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
};

// out without the progress lines a long phase prints when stderr is not a terminal ("sphray:
// making the scene random:16777216, 2.0 s elapsed"), which a loaded machine may reach.
std::string without_progress(const std::string& out) {
  std::string kept;
  for (std::size_t at = 0; at < out.size();) {
    const std::size_t end = std::min(out.find('\n', at), out.size());
    const std::string line = out.substr(at, end - at);
    if (!(line.starts_with("sphray: ") && line.ends_with(" elapsed")))
      kept += out.substr(at, end + 1 - at);
    at = end + 1;
  }
  return kept;
}

Outcome run(const ChildSetup& setup) {
  return Child(setup).wait();
}

using sphray::test::read_bytes;
using sphray::test::write_text;

// The size of a PNG, decoded independently of the code that wrote it; {0, 0} if it is none.
std::pair<int, int> png_size(const fs::path& path) {
  int w = 0, h = 0, channels = 0;
  stbi_uc* data = stbi_load(path.c_str(), &w, &h, &channels, 3);
  if (data == nullptr) return {0, 0};
  stbi_image_free(data);
  return {w, h};
}

mode_t mode_of(const fs::path& path) {
  struct stat st {};
  ::stat(path.c_str(), &st);
  return st.st_mode & 07777;
}

class Hostile : public ::testing::Test {
 protected:
  void SetUp() override {
    // The process id too: two build trees' tests may run at once and share /tmp.
    dir_ = fs::temp_directory_path() /
           ("sphray-hostile-" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "-" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    fs::permissions(dir_, fs::perms::all, fs::perm_options::add);
    std::error_code ignored;
    for (const auto& entry : fs::recursive_directory_iterator(dir_, ignored))
      fs::permissions(entry.path(), fs::perms::owner_all, fs::perm_options::add, ignored);
    fs::remove_all(dir_);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::vector<std::string> names() const {
    std::vector<std::string> all;
    for (const auto& entry : fs::directory_iterator(dir_))
      all.push_back(entry.path().filename().string());
    std::sort(all.begin(), all.end());
    return all;
  }
  // Waits until a named temporary (SPHRAY_TMPFILE=named) exists: the render is under way.
  bool wait_for_temporary() const {
    for (int i = 0; i < 2000; ++i) {
      for (const auto& entry : fs::directory_iterator(dir_))
        if (entry.path().filename().string().starts_with(".sphray-")) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }
  fs::path dir_;
};

const std::string kOld = "the previous image, which a failed run must leave as it is";

// A render long enough (a second or more) to be signalled while it runs.
std::vector<std::string> long_render(const std::string& output) {
  return {"render", "-s",   "rtiow-final", "-m", "shaded", "-W", "4000",
          "-H",     "2250", "--spp",       "4",  "-q",     "-o", output};
}

// --- Crashes where a clear error is promised -------------------------------------------------

TEST_F(Hostile, SceneNameTooLongIsAnErrorNotACrash) {
  std::string name = path(std::string(300, 'n'));
  Outcome o = run({.args = {"render", "-s", name, "-o", path("out.png")}});
  EXPECT_EQ(o.exit, 2) << o.out;
  EXPECT_EQ(o.out, "sphray: " + name + ": cannot read the scene file (File name too long)\n");
}

TEST_F(Hostile, SceneInAFolderTheUserCannotSearchIsAnErrorNotACrash) {
  fs::create_directory(path("secret"));
  write_text(path("secret/x"), "{}");
  // Mode 000: not even its owner may search it. Root, which may search anything, runs sphray
  // without that capability (from its bounding set, so the exec does not give it back); a
  // change of user would also have to reach the binary, which a checkout under /root denies.
  fs::permissions(path("secret"), fs::perms::none);
  Outcome o = run({.args = {"render", "-s", path("secret/x"), "-o", path("out.png")},
                   .without_dac_override = true});
  ASSERT_NE(o.exit, 122) << "could not drop CAP_DAC_OVERRIDE and CAP_DAC_READ_SEARCH";
  EXPECT_EQ(o.exit, 2) << o.out;
  EXPECT_EQ(o.out,
            "sphray: " + path("secret/x") + ": cannot read the scene file (Permission denied)\n");
}

TEST_F(Hostile, SceneSymlinkLoopIsAnErrorNotACrash) {
  fs::create_symlink("loop", path("loop"));
  Outcome o = run({.args = {"render", "-s", path("loop"), "-o", path("out.png")}});
  EXPECT_EQ(o.exit, 2) << o.out;
  EXPECT_EQ(o.out, "sphray: " + path("loop") +
                       ": cannot read the scene file (Too many levels of symbolic links)\n");
}

TEST_F(Hostile, ImageTooLargeForTheMemoryLimitIsRefusedBeforeRendering) {
  if (kSanitized) GTEST_SKIP() << "RLIMIT_AS cannot be set under a sanitizer";
  write_text(path("out.png"), kOld);
  for (const char* tmpfile : {"SPHRAY_TMPFILE=unnamed", "SPHRAY_TMPFILE=named"}) {
    Outcome o = run({.args = {"render", "-s", "single", "-m", "flat", "--spp", "1", "-W", "16384",
                              "-H", "16384", "-o", path("out.png")},
                     .env = {tmpfile},
                     .limits = {{RLIMIT_AS, rlim_t{600000} * 1024}}});
    EXPECT_EQ(o.exit, 1) << o.out;
    // 16384 x 16384 x 3 bytes is 768 MiB for the image alone.
    EXPECT_TRUE(
        o.out.starts_with("sphray: " + path("out.png") + ": a 16384x16384 image needs about "))
        << o.out;
    EXPECT_NE(o.out.find("GiB of memory, which this process cannot get (ulimit -v is 586 MiB)"),
              std::string::npos)
        << o.out;
    EXPECT_EQ(read_bytes(path("out.png")), kOld);
    EXPECT_EQ(names(), std::vector<std::string>{"out.png"}) << tmpfile;
  }
}

TEST_F(Hostile, PpmTooLargeForTheMemoryLimitIsRefusedBeforeRendering) {
  if (kSanitized) GTEST_SKIP() << "RLIMIT_AS cannot be set under a sanitizer";
  Outcome o =
      run({.args = {"render", "-s", "single", "-W", "16384", "-H", "16384", "-o", path("out.ppm")},
           .limits = {{RLIMIT_AS, rlim_t{600000} * 1024}}});
  EXPECT_EQ(o.exit, 1) << o.out;
  EXPECT_TRUE(o.out.starts_with("sphray: " + path("out.ppm") + ": a 16384x16384 image needs"))
      << o.out;
  EXPECT_TRUE(names().empty());
}

TEST_F(Hostile, OutOfMemoryWhileBuildingTheSceneIsAMessageNotACrash) {
  if (kSanitized) GTEST_SKIP() << "RLIMIT_AS cannot be set under a sanitizer";
  // 16,777,216 spheres take more than 600 MB before any image is asked for: std::bad_alloc
  // from the scene, caught in the command.
  write_text(path("out.png"), kOld);
  Outcome o = run(
      {.args = {"render", "-s", "random:16777216", "-W", "16", "-H", "9", "-o", path("out.png")},
       .limits = {{RLIMIT_AS, rlim_t{600000} * 1024}}});
  EXPECT_EQ(o.exit, 1) << o.out;
  EXPECT_EQ(without_progress(o.out),
            "sphray: random:16777216: out of memory while building or rendering the scene\n");
  EXPECT_EQ(read_bytes(path("out.png")), kOld);
  EXPECT_EQ(names(), std::vector<std::string>{"out.png"});
}

// --- Memory that grew with the square of the input -------------------------------------------

TEST_F(Hostile, DeepJsonIsRefusedUnderAMemoryLimit) {
  if (kSanitized) GTEST_SKIP() << "RLIMIT_AS cannot be set under a sanitizer";
  // 100,000 levels (200 KB): the old locator died of bad_alloc under 4 GB. 256 MB here.
  constexpr std::size_t kDepth = 100000;
  write_text(path("deep.json"), "{\"spheres\": " + std::string(kDepth, '[') +
                                    std::string(kDepth, ']') + ", \"x\": 1}");
  Outcome o = run({.args = {"render", "-s", path("deep.json"), "-o", path("out.png")},
                   .limits = {{RLIMIT_AS, rlim_t{256} << 20}}});
  EXPECT_EQ(o.exit, 2) << o.out;
  EXPECT_EQ(o.out, "sphray: " + path("deep.json") +
                       ":1:76: expected at most 64 levels of nested arrays and objects\n");
}

// --- The output file ---------------------------------------------------------------------------

TEST_F(Hostile, PrivateOutputKeepsMode600) {
  write_text(path("out.png"), kOld);
  fs::permissions(path("out.png"), fs::perms::owner_read | fs::perms::owner_write);
  Outcome o = run(
      {.args = {"render", "-s", "single", "-W", "32", "-H", "18", "-q", "-o", path("out.png")}});
  EXPECT_EQ(o.exit, 0) << o.out;
  EXPECT_EQ(png_size(path("out.png")), std::make_pair(32, 18));
  EXPECT_EQ(mode_of(path("out.png")), 0600u);
}

TEST_F(Hostile, NewOutputGetsTheModeTheUmaskGives) {
  const mode_t mask = ::umask(027);  // the child inherits it
  Outcome o =
      run({.args = {"render", "-s", "single", "-W", "8", "-H", "8", "-q", "-o", path("new.png")}});
  ::umask(mask);
  EXPECT_EQ(o.exit, 0) << o.out;
  EXPECT_EQ(mode_of(path("new.png")), 0640u);  // 0666 less 027, as open(2) would give
}

TEST_F(Hostile, OutputOwnerAndGroupAreKeptWherePermitted) {
  if (::geteuid() != 0) GTEST_SKIP() << "only root may give a file to another user";
  write_text(path("out.png"), kOld);
  ASSERT_EQ(::chown(path("out.png").c_str(), 65534, 65534), 0);
  fs::permissions(path("out.png"), static_cast<fs::perms>(0640));
  Outcome o = run(
      {.args = {"render", "-s", "single", "-W", "32", "-H", "18", "-q", "-o", path("out.png")}});
  EXPECT_EQ(o.exit, 0) << o.out;
  struct stat st {};
  ASSERT_EQ(::stat(path("out.png").c_str(), &st), 0);
  EXPECT_EQ(st.st_uid, 65534u);
  EXPECT_EQ(st.st_gid, 65534u);
  EXPECT_EQ(st.st_mode & 07777, 0640u);
  EXPECT_EQ(png_size(path("out.png")), std::make_pair(32, 18));
}

TEST_F(Hostile, ReadOnlyOutputIsRefusedUnlessForced) {
  write_text(path("out.png"), kOld);
  fs::permissions(path("out.png"), static_cast<fs::perms>(0444));
  std::vector<std::string> args{"render", "-s", "single", "-W", "32",
                                "-H",     "18", "-q",     "-o", path("out.png")};
  Outcome refused = run({.args = args});
  EXPECT_EQ(refused.exit, 2) << refused.out;
  EXPECT_EQ(refused.out, "sphray: " + path("out.png") +
                             ": the output file is read-only (use --force to replace it)\n");
  EXPECT_EQ(read_bytes(path("out.png")), kOld);
  args.push_back("--force");
  Outcome forced = run({.args = args});
  EXPECT_EQ(forced.exit, 0) << forced.out;
  EXPECT_EQ(png_size(path("out.png")), std::make_pair(32, 18));
  EXPECT_EQ(mode_of(path("out.png")), 0444u);  // still read-only, like the file it replaced
  EXPECT_EQ(names(), std::vector<std::string>{"out.png"});
}

TEST_F(Hostile, SymlinkOutputIsWrittenThroughToItsTarget) {
  fs::create_directory(path("real"));
  write_text(path("real/image.png"), kOld);
  fs::permissions(path("real/image.png"), static_cast<fs::perms>(0600));
  fs::create_symlink("real/image.png", path("link.png"));  // relative, from dir_
  Outcome o = run(
      {.args = {"render", "-s", "single", "-W", "32", "-H", "18", "-q", "-o", path("link.png")}});
  EXPECT_EQ(o.exit, 0) << o.out;
  EXPECT_TRUE(fs::is_symlink(path("link.png")));
  EXPECT_EQ(fs::read_symlink(path("link.png")), "real/image.png");
  EXPECT_EQ(png_size(path("real/image.png")), std::make_pair(32, 18));
  EXPECT_EQ(mode_of(path("real/image.png")), 0600u);
  EXPECT_EQ(names(), (std::vector<std::string>{"link.png", "real"}));
  EXPECT_EQ(fs::directory_iterator(path("real"))->path().filename(), "image.png");
}

TEST_F(Hostile, DanglingSymlinkOutputIsRefused) {
  fs::create_symlink("nowhere/image.png", path("link.png"));
  Outcome o = run({.args = {"render", "-s", "single", "-q", "-o", path("link.png")}});
  EXPECT_EQ(o.exit, 2) << o.out;
  EXPECT_EQ(o.out, "sphray: " + path("link.png") +
                       ": expected an output file, got a dangling symbolic link\n");
}

TEST_F(Hostile, HardLinkedOutputIsSplitFromItsOtherNames) {
  write_text(path("out.png"), kOld);
  fs::create_hard_link(path("out.png"), path("other.png"));
  Outcome o = run(
      {.args = {"render", "-s", "single", "-W", "32", "-H", "18", "-q", "-o", path("out.png")}});
  EXPECT_EQ(o.exit, 0) << o.out;
  EXPECT_EQ(png_size(path("out.png")), std::make_pair(32, 18));
  EXPECT_EQ(read_bytes(path("other.png")), kOld);  // the other name keeps the old file
  EXPECT_EQ(fs::hard_link_count(path("out.png")), 1u);
  EXPECT_EQ(fs::hard_link_count(path("other.png")), 1u);
}

TEST_F(Hostile, DirectoryOutputIsRefusedBeforeRendering) {
  fs::create_directory(path("out.png"));
  ChildSetup setup{
      .args = {"render", "-s", "single", "-W", "16384", "-H", "16384", "-o", path("out.png")}};
  // Under a limit too small for the image, the memory check (which precedes the render) would
  // answer with exit 1 if the output were looked at any later.
  if (!kSanitized) setup.limits = {{RLIMIT_AS, rlim_t{600000} * 1024}};
  Outcome o = run(setup);
  EXPECT_EQ(o.exit, 2) << o.out;
  EXPECT_EQ(o.out, "sphray: " + path("out.png") + ": expected an output file, got a directory\n");
  EXPECT_TRUE(fs::is_directory(path("out.png")));
  EXPECT_EQ(names(), std::vector<std::string>{"out.png"});
}

TEST_F(Hostile, OutputNameOf244CharactersIsWritten) {
  const std::string name = std::string(240, 'o') + ".png";  // 255 is the usual name limit
  for (const char* tmpfile : {"SPHRAY_TMPFILE=unnamed", "SPHRAY_TMPFILE=named"}) {
    Outcome o =
        run({.args = {"render", "-s", "single", "-W", "32", "-H", "18", "-q", "-o", path(name)},
             .env = {tmpfile}});
    EXPECT_EQ(o.exit, 0) << tmpfile << ": " << o.out;
    EXPECT_EQ(png_size(path(name)), std::make_pair(32, 18)) << tmpfile;
    EXPECT_EQ(names(), std::vector<std::string>{name}) << tmpfile;
  }
}

// --- Signals and limits -------------------------------------------------------------------------

TEST_F(Hostile, InheritedIgnoredSighupStaysIgnored) {
  // This render runs to its end: about a second, scaled down by SPHRAY_TEST_SCALE (0.1 under
  // the sanitizers, which render some 50 times slower), long enough to be signalled while it
  // runs (the signal follows the temporary's appearance by a few milliseconds).
  const char* scale_text = std::getenv("SPHRAY_TEST_SCALE");
  const double scale = scale_text != nullptr ? std::atof(scale_text) : 1.0;
  const int width = static_cast<int>(2000 * std::sqrt(scale > 0 ? scale : 1.0));
  const int height = width * 9 / 16;
  std::vector<std::string> args = long_render(path("out.png"));
  args[6] = std::to_string(width);
  args[8] = std::to_string(height);
  Child child({.args = args,
               .env = {"SPHRAY_TMPFILE=named"},
               .ignored_signals = {SIGHUP}});  // as nohup leaves it
  ASSERT_TRUE(wait_for_temporary());
  child.signal(SIGHUP);
  Outcome o = child.wait();
  EXPECT_EQ(o.signal, 0);
  EXPECT_EQ(o.exit, 0) << o.out;
  EXPECT_EQ(png_size(path("out.png")), std::make_pair(width, height));
  EXPECT_EQ(names(), std::vector<std::string>{"out.png"});
}

class HostileSignal : public Hostile, public ::testing::WithParamInterface<int> {};

TEST_P(HostileSignal, TemporaryIsRemovedAndTheRunDiesOfTheSignal) {
  write_text(path("out.png"), kOld);
  Child child({.args = long_render(path("out.png")), .env = {"SPHRAY_TMPFILE=named"}});
  ASSERT_TRUE(wait_for_temporary());
  child.signal(GetParam());
  Outcome o = child.wait();
  EXPECT_EQ(o.signal, GetParam()) << o.out;
  EXPECT_EQ(read_bytes(path("out.png")), kOld);
  EXPECT_EQ(names(), std::vector<std::string>{"out.png"});
}

INSTANTIATE_TEST_SUITE_P(Fatal, HostileSignal, ::testing::Values(SIGQUIT, SIGTERM, SIGINT, SIGHUP),
                         [](const auto& info) { return std::string(sigabbrev_np(info.param)); });

TEST_F(Hostile, FileSizeLimitRemovesTheTemporary) {
  write_text(path("out.png"), kOld);
  for (const char* tmpfile : {"SPHRAY_TMPFILE=unnamed", "SPHRAY_TMPFILE=named"}) {
    // The PNG of a 256x256 shaded render is far above 4 KiB: the write raises SIGXFSZ.
    Outcome o = run({.args = {"render", "-s", "three", "-m", "shaded", "-W", "256", "-H", "256",
                              "-q", "-o", path("out.png")},
                     .env = {tmpfile},
                     .limits = {{RLIMIT_FSIZE, rlim_t{4096}}}});
    EXPECT_EQ(o.signal, SIGXFSZ) << tmpfile << ": " << o.out;
    EXPECT_EQ(read_bytes(path("out.png")), kOld);
    EXPECT_EQ(names(), std::vector<std::string>{"out.png"}) << tmpfile;
  }
}

TEST_F(Hostile, TemporaryOfAKilledRunIsRemovedByTheNextRunOnTheSameTarget) {
  write_text(path("out.png"), kOld);
  {
    Child child({.args = long_render(path("out.png")), .env = {"SPHRAY_TMPFILE=named"}});
    ASSERT_TRUE(wait_for_temporary());
    child.signal(SIGKILL);
    EXPECT_EQ(child.wait().signal, SIGKILL);
  }
  ASSERT_EQ(names().size(), 2u) << "SIGKILL cannot be caught: its temporary stays";
  const std::string stale = names()[0];
  EXPECT_TRUE(stale.starts_with(".sphray-") && stale.ends_with(".tmp")) << stale;
  // A temporary of another target is none of this run's business.
  write_text(path(".sphray-0123456789abcdef-1-0.tmp"), "another target's");
  Outcome o = run(
      {.args = {"render", "-s", "single", "-W", "32", "-H", "18", "-q", "-o", path("out.png")}});
  EXPECT_EQ(o.exit, 0) << o.out;
  EXPECT_EQ(names(), (std::vector<std::string>{".sphray-0123456789abcdef-1-0.tmp", "out.png"}));
}

TEST_F(Hostile, UnnamedTemporaryLeavesNothingAfterSigkill) {
  write_text(path("out.png"), kOld);
  Child child({.args = long_render(path("out.png")), .env = {"SPHRAY_TMPFILE=unnamed"}});
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // no sync point: nothing named
  child.signal(SIGKILL);
  EXPECT_EQ(child.wait().signal, SIGKILL);
  EXPECT_EQ(read_bytes(path("out.png")), kOld);
  EXPECT_EQ(names(), std::vector<std::string>{"out.png"});
}

// --- More, from the same hostile run ------------------------------------------------------------

TEST_F(Hostile, ClosedStderrNeverReachesTheImage) {
  const std::vector<std::string> args{"render", "-s", "three", "-W", "64", "-H", "36", "-q", "-o"};
  auto with_output = [&](const std::string& name) {
    std::vector<std::string> a = args;
    a.push_back(path(name));
    return a;
  };
  // The warning that would land in the image: an unknown SPHRAY_ISA, printed on stderr.
  Outcome open_stderr = run({.args = with_output("open.png"), .env = {"SPHRAY_ISA=nonsense"}});
  ASSERT_EQ(open_stderr.exit, 0) << open_stderr.out;
  ASSERT_NE(open_stderr.out.find("SPHRAY_ISA"), std::string::npos) << "no warning to misdirect";
  Outcome closed = run({.args = with_output("closed.png"),
                        .env = {"SPHRAY_ISA=nonsense", "SPHRAY_TMPFILE=named"},
                        .close_stderr = true});
  EXPECT_EQ(closed.exit, 0);
  Outcome unnamed = run({.args = with_output("unnamed.png"),
                         .env = {"SPHRAY_ISA=nonsense", "SPHRAY_TMPFILE=unnamed"},
                         .close_stderr = true});
  EXPECT_EQ(unnamed.exit, 0);
  EXPECT_EQ(png_size(path("closed.png")), std::make_pair(64, 36));
  EXPECT_EQ(read_bytes(path("closed.png")), read_bytes(path("open.png")));
  EXPECT_EQ(read_bytes(path("unnamed.png")), read_bytes(path("open.png")));
}

TEST_F(Hostile, BvhAndBruteForceWriteTheSameBytes) {
  for (const char* scene : {"three", "random:3", "random:5"}) {
    for (const char* mode : {"normals", "shaded"}) {
      std::string images[2];
      int i = 0;
      for (const char* accel : {"bvh", "brute"}) {
        const std::string out = path(std::string(accel) + ".ppm");  // P3: every byte a pixel
        Outcome o = run({.args = {"render", "-s", scene, "-m", mode, "--accel", accel, "-W", "400",
                                  "-H", "225", "--spp", "4", "-q", "-o", out}});
        ASSERT_EQ(o.exit, 0) << o.out;
        images[i++] = read_bytes(out);
      }
      ASSERT_FALSE(images[0].empty());
      EXPECT_TRUE(images[0] == images[1]) << scene << " " << mode;
    }
  }
}

TEST_F(Hostile, SeedOutOfRangeIsRefusedLikeSpp) {
  for (const char* seed : {"-1", "1e23", "18446744073709551616", "0x10", ""}) {
    Outcome o = run({.args = {"render", "-s", "single", "--seed", seed, "-o", path("out.png")}});
    EXPECT_EQ(o.exit, 2) << seed;
    EXPECT_EQ(o.out, std::string("sphray: --seed: Value ") + seed +
                         " not in range 0 to 18446744073709551615 (see sphray --help)\n")
        << seed;
  }
  Outcome largest = run({.args = {"render", "-s", "single", "-W", "8", "-H", "8", "--seed",
                                  "18446744073709551615", "-q", "-o", path("out.png")}});
  EXPECT_EQ(largest.exit, 0) << largest.out;
}

TEST_F(Hostile, OneSideGivenKeepsTheScenesAspect) {
  write_text(path("wide.json"), R"({"width": 300, "height": 100, "spheres": []})");
  for (auto [flag, side, w, h] : {std::tuple{"-W", "150", 150, 50}, std::tuple{"-H", "50", 150, 50},
                                  std::tuple{"-W", "100", 100, 33}}) {
    Outcome o =
        run({.args = {"render", "-s", path("wide.json"), flag, side, "-q", "-o", path("out.png")}});
    EXPECT_EQ(o.exit, 0) << o.out;
    EXPECT_EQ(png_size(path("out.png")), std::make_pair(w, h)) << flag << " " << side;
  }
}

TEST_F(Hostile, QuietSilencesOneTbbForManyThreads) {
  Outcome o = run({.args = {"render", "-s", "single", "-W", "32", "-H", "18", "-j", "1024", "-q",
                            "-o", path("out.png")}});
  EXPECT_EQ(o.exit, 0);
  EXPECT_EQ(o.out, "");
}

TEST_F(Hostile, DevZeroSceneIsCappedWithAMessage) {
  Outcome o = run({.args = {"render", "-s", "/dev/zero", "-o", path("out.png")}});
  EXPECT_EQ(o.exit, 2);
  EXPECT_EQ(o.out, "sphray: /dev/zero: expected a scene file of at most 64 MiB, got more\n");
}

TEST_F(Hostile, FifoWithoutAWriterIsRefusedAfterTheWait) {
  ASSERT_EQ(::mkfifo(path("scene.json").c_str(), 0600), 0);
  Outcome o = run({.args = {"render", "-s", path("scene.json"), "-o", path("out.png")}});
  EXPECT_EQ(o.exit, 2);
  // The wait is long enough for a progress line (stderr is not a terminal) before the message.
  EXPECT_EQ(without_progress(o.out),
            "sphray: " + path("scene.json") +
                ": expected a writer on the FIFO, got no data within 5 s\n");
}

TEST_F(Hostile, DashReadsTheSceneFromStandardInput) {
  Outcome o = run({.args = {"render", "-s", "-", "-q", "-o", path("out.png")},
                   .stdin_text = R"({"width": 20, "height": 10, "spheres": []})"});
  EXPECT_EQ(o.exit, 0) << o.out;
  EXPECT_EQ(png_size(path("out.png")), std::make_pair(20, 10));
  Outcome bad = run(
      {.args = {"render", "-s", "-", "-o", path("out.png")}, .stdin_text = R"({"spheres": 1})"});
  EXPECT_EQ(bad.exit, 2);
  EXPECT_TRUE(bad.out.starts_with("sphray: <stdin>:1:13: ")) << bad.out;
}

TEST_F(Hostile, FullStdoutIsAFailure) {
  const std::string full = "sphray: standard output: cannot write (No space left on device)\n";
  for (std::vector<std::string> args : {std::vector<std::string>{"scenes"}, {"info"}, {"--help"}}) {
    Outcome o = run({.args = args, .stdout_path = "/dev/full"});
    EXPECT_EQ(o.exit, 1) << args[0];
    EXPECT_EQ(o.out, full) << args[0];
  }
  // The summary line: the image is written, but the run did not say so.
  Outcome o =
      run({.args = {"render", "-s", "single", "-W", "32", "-H", "18", "-o", path("out.png")},
           .stdout_path = "/dev/full"});
  EXPECT_EQ(o.exit, 1);
  EXPECT_EQ(o.out, full);
  EXPECT_EQ(png_size(path("out.png")), std::make_pair(32, 18));
}

}  // namespace
