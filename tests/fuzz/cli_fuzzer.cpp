// Command-line fuzzer: the sphray command's main() (render/tools/sphray.cpp, compiled into this
// target with main renamed to sphray_cli_main) runs in-process on fuzzed arguments. Every run
// must return 0, 1 or 2, and must not crash, leak, hang or throw. A run that fails (status 1 or
// 2) must leave every file that was there byte-identical, and no run may leave a temporary file
// behind.
//
// The input is the argument list, one argument per line. Two things keep each run small and
// harmless, and change nothing else:
// - every '/' becomes '_', so all paths stay in the scratch folder the fuzzer works in (it runs
//   as whatever user starts it, root in CI), and in an argument that names random:N, runs of
//   more than 4 digits are cut to 4, so a scene has at most 9999 spheres;
// - render() is wrapped (the linker's --wrap, see CMakeLists.txt): a valid size, sample count
//   or path depth above 16x16 pixels, 2 samples and 8 rays is lowered to that before the real
//   render() runs.
//   Invalid values pass through untouched, so the refusals are the real ones.
// - `sphray bench` is wrapped the same way, and its wrapper measures nothing: the fuzzer covers
//   the command's parsing and refusals of bench's options, not timed runs of seconds each
//   (tests/render/bench_cli_test.cpp runs them).
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "sphray/render/renderer.hpp"

int sphray_cli_main(int argc, char** argv);

namespace sphray::render {
// The real render() and its wrapper, by the symbol names --wrap gives them. If render()'s
// signature changes, the link fails with an undefined __real_ symbol: update both names here
// and the --wrap option in CMakeLists.txt.
Image real_render(const Scene&, const RenderOptions&, const Progress&, RenderStats*) asm(
    "__real__ZN6sphray6render6renderERKNS0_5SceneERKNS0_13RenderOptionsERKSt8functionIFvmmRKNS0_"
    "9RayCountsEEEPNS0_11RenderStatsE");
Image bounded_render(const Scene&, const RenderOptions&, const Progress&, RenderStats*) asm(
    "__wrap__ZN6sphray6render6renderERKNS0_5SceneERKNS0_13RenderOptionsERKSt8functionIFvmmRKNS0_"
    "9RayCountsEEEPNS0_11RenderStatsE");

Image bounded_render(const Scene& scene, const RenderOptions& options, const Progress& progress,
                     RenderStats* stats) {
  RenderOptions small = options;
  if (small.width > 16) small.width = 16;
  if (small.height > 16) small.height = 16;
  if (small.spp > 2) small.spp = 2;
  if (small.max_depth > 8) small.max_depth = 8;
  return real_render(scene, small, progress, stats);
}
}  // namespace sphray::render

namespace sphray::render::bench {
struct BenchArgs;
int bounded_run_bench(const BenchArgs&) asm(
    "__wrap__ZN6sphray6render5bench9run_benchERKNS1_9BenchArgsE");
int bounded_run_bench(const BenchArgs&) {
  return 0;
}
}  // namespace sphray::render::bench

namespace {

namespace fs = std::filesystem;

// The files every run starts with: scenes to load (good and bad) and an image to overwrite.
const std::map<std::string, std::string> kFixtures = {
    {"scene.json", R"({"camera": {"lookfrom": [0, 0, 3], "lookat": [0, 0, 0], "vfov": 40},
                      "spheres": [{"center": [0, 0, 0], "radius": 1, "color": [1, 0, 0]}]})"},
    {"bad.json", R"({"spheres": [{"center": [0, 0], "radius": -1}]})"},
    {"empty.json", ""},
    {"old.png", "not really a PNG, but it must survive every failed run"},
    {"old.ppm", "P3\n1 1\n255\n0 0 0\n"},
};

std::string read(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void write(const fs::path& file, const std::string& text) {
  std::ofstream(file, std::ios::binary) << text;
}

// The scratch folder, restored to exactly the fixtures (and a folder "dir.json") before a run.
void reset_scratch() {
  for (const auto& entry : fs::directory_iterator("."))
    if (!kFixtures.contains(entry.path().filename().string()) &&
        entry.path().filename() != "dir.json")
      fs::remove_all(entry.path());
  for (const auto& [name, text] : kFixtures)
    if (read(name) != text) write(name, text);
  fs::create_directory("dir.json");
}

// One argument per line; '/' becomes '_'; in an argument naming random:N, digit runs are cut
// to 4 digits.
std::string harmless(std::string arg) {
  std::replace(arg.begin(), arg.end(), '/', '_');
  if (arg.find("random:") == std::string::npos) return arg;
  std::string cut;
  int digits = 0;
  for (char ch : arg) {
    digits = (ch >= '0' && ch <= '9') ? digits + 1 : 0;
    if (digits <= 4) cut.push_back(ch);
  }
  return cut;
}

std::vector<std::string> arguments(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> args{"sphray"};
  if (size == 0) return args;
  std::istringstream lines(std::string(reinterpret_cast<const char*>(data), size));
  std::string line;
  while (std::getline(lines, line))
    args.push_back(harmless(line));
  if (data[size - 1] == '\n') args.push_back("");
  return args;
}

[[noreturn]] void fail(const std::string& what, const std::vector<std::string>& args) {
  std::string line;
  for (const auto& a : args)
    line += " [" + a + "]";
  std::fprintf(stderr, "cli fuzzer: %s; arguments:%s\n", what.c_str(), line.c_str());
  std::abort();
}

// After the run: a failure changed no fixture, and nothing but the fixtures and (after a
// success) the image written is left.
void check_files(int status, const std::vector<std::string>& args) {
  for (const auto& entry : fs::directory_iterator(".")) {
    const std::string name = entry.path().filename().string();
    const auto fixture = kFixtures.find(name);
    if (fixture != kFixtures.end()) {
      if (status != 0 && read(name) != fixture->second)
        fail(name + " changed by a failed run", args);
      continue;
    }
    if (name == "dir.json") continue;
    if (status != 0) fail("a failed run left " + name + " behind", args);
    if (name.ends_with(".tmp")) fail("a temporary file was left behind: " + name, args);
  }
}

}  // namespace

std::string scratch;  // the folder every run works in

// Runs body in the scratch folder, then returns to where libFuzzer works (its corpus, its
// dictionary and the inputs it saves are relative to that).
template <class Body>
void in_scratch(Body&& body) {
  const int home = ::open(".", O_RDONLY | O_DIRECTORY);
  if (home < 0 || ::chdir(scratch.c_str()) != 0) std::abort();
  body();
  if (::fchdir(home) != 0) std::abort();
  ::close(home);
}

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // A scratch folder of our own: every path the fuzzed arguments can name lies in it.
  char dir[] = "/tmp/sphray-cli-fuzz-XXXXXX";
  if (::mkdtemp(dir) == nullptr) std::abort();
  scratch = dir;
  std::atexit([] {
    std::error_code ignored;
    fs::remove_all(scratch, ignored);
  });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> args = arguments(data, size);
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);

  in_scratch([&] {
    reset_scratch();
    // The command installs handlers for SIGINT, SIGTERM and SIGHUP during a render; put back
    // the fuzzer's own afterwards.
    struct sigaction saved[3];
    const int signals[3] = {SIGINT, SIGTERM, SIGHUP};
    for (int i = 0; i < 3; ++i)
      sigaction(signals[i], nullptr, &saved[i]);
    const int status = sphray_cli_main(static_cast<int>(args.size()), argv.data());
    for (int i = 0; i < 3; ++i)
      sigaction(signals[i], &saved[i], nullptr);
    std::fflush(stdout);

    if (status != 0 && status != 1 && status != 2)
      fail("exit status " + std::to_string(status), args);
    check_files(status, args);
  });
  return 0;
}
