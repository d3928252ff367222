// The sphray command, run as a process: exit statuses, one-line messages, files written and
// read back (PNG with stb_image, P3 PPM parsed here), and existing files left untouched.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <unistd.h>

#include <sphray/sphray.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include "command/progress_report.hpp"
#include "command_run.hpp"
#include "test_files.hpp"

namespace {

namespace fs = std::filesystem;

using Result = sphray::test::CommandResult;

Result run(const std::string& args) {
  return sphray::test::run_sphray(args);
}

using sphray::test::read_bytes;
using sphray::test::write_text;

class Cli : public sphray::test::ScratchDirTest {
 protected:
  Cli() : ScratchDirTest("sphray-cli-") {}
  std::size_t files_in_dir() const {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir_), {}));
  }
};

TEST_F(Cli, RendersAPngThatReadsBack) {
  Result r = run("render -s single -W 41 -H 23 --spp 1 -o " + path("a.png"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("41x23, 1 spp"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("rays/s"), std::string::npos) << r.out;
  int w = 0, h = 0, channels = 0;
  stbi_uc* data = stbi_load(path("a.png").c_str(), &w, &h, &channels, 3);
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(w, 41);
  EXPECT_EQ(h, 23);
  // The centre pixel: the normal (0,0,1) as 0.5 * (n + 1), int(255.999 * c).
  const stbi_uc* centre = data + 3 * (11 * 41 + 20);
  EXPECT_EQ(centre[0], 127);
  EXPECT_EQ(centre[1], 127);
  EXPECT_EQ(centre[2], 255);
  stbi_image_free(data);
  EXPECT_EQ(files_in_dir(), 1u);  // no temporary file left behind
}

TEST_F(Cli, PpmIsP3WithTheSamePixelsAsThePng) {
  ASSERT_EQ(run("render -s three -m shaded -W 32 -H 18 -q -o " + path("a.png")).status, 0);
  ASSERT_EQ(run("render -s three -m shaded -W 32 -H 18 -q -o " + path("a.ppm")).status, 0);
  int w = 0, h = 0, channels = 0;
  stbi_uc* png = stbi_load(path("a.png").c_str(), &w, &h, &channels, 3);
  ASSERT_NE(png, nullptr);
  std::istringstream ppm(read_bytes(path("a.ppm")));
  std::string magic;
  int pw = 0, ph = 0, max = 0;
  ppm >> magic >> pw >> ph >> max;
  EXPECT_EQ(magic, "P3");
  EXPECT_EQ(pw, 32);
  EXPECT_EQ(ph, 18);
  EXPECT_EQ(max, 255);
  std::vector<int> values;
  for (int v; ppm >> v;)
    values.push_back(v);
  ASSERT_EQ(values.size(), 32u * 18u * 3u);
  for (std::size_t i = 0; i < values.size(); ++i)
    ASSERT_EQ(values[i], png[i]) << "value " << i;
  stbi_image_free(png);
}

// Path mode through the command: the summary counts camera and bounce rays, one image per
// seed whatever the thread count, and a time limit that is up at once still writes 1 spp.
TEST_F(Cli, PathModeReportsBounceRaysAndIsTheSameOnAnyThreads) {
  const std::string common = "render -m path -s three -W 32 -H 18 --spp 4 --seed 5 ";
  Result one = run(common + "-j 1 -o " + path("one.png"));
  ASSERT_EQ(one.status, 0) << one.out;
  EXPECT_NE(one.out.find("32x18, 4 spp, path"), std::string::npos) << one.out;
  EXPECT_NE(one.out.find("2304 camera + "), std::string::npos) << one.out;  // 32 * 18 * 4
  EXPECT_EQ(one.out.find(" + 0 bounce"), std::string::npos) << one.out;
  EXPECT_NE(one.out.find("rays/s"), std::string::npos) << one.out;
  Result two = run(common + "-j 2 -o " + path("two.png"));
  ASSERT_EQ(two.status, 0) << two.out;
  EXPECT_EQ(read_bytes(path("one.png")), read_bytes(path("two.png")));
  Result limited = run(common + "--time-limit 1e-9 -o " + path("limited.png"));
  ASSERT_EQ(limited.status, 0) << limited.out;
  EXPECT_NE(limited.out.find("32x18, 1 spp, path"), std::string::npos) << limited.out;
  EXPECT_NE(limited.out.find("time limit reached"), std::string::npos) << limited.out;
}

TEST_F(Cli, QuietPrintsNothing) {
  Result r = run("render -s single -W 16 -H 9 -q -o " + path("q.png"));
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out, "");
}

// On a terminal the command names each phase as it starts (drawn at once, so even a run this
// short shows them), with the elapsed time, then clears the line before the summary.
TEST_F(Cli, ProgressOnATerminalNamesThePhasesInOrder) {
  const Result r =
      sphray::test::run_sphray_on_terminal("render -s random:300 -W 32 -H 18 -o " + path("t.png"));
  ASSERT_EQ(r.status, 0) << r.out;
  std::size_t at = 0;
  for (const std::string& phase :
       std::vector<std::string>{"making the scene random:300", "building the tree of 300 spheres",
                                "rendering [", "writing " + path("t.png") + " ... ", "wrote "}) {
    const std::size_t found = r.out.find(phase, at);
    ASSERT_NE(found, std::string::npos) << phase << " after offset " << at << " in " << r.out;
    at = found;
  }
  EXPECT_NE(r.out.find(" elapsed"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\r\033[K"), std::string::npos) << r.out;  // the line is cleared
}

TEST_F(Cli, ProgressNamesAFileSceneAndQuietSilencesTheTerminal) {
  write_text(path("s.json"), R"({"spheres": [{"center": [0, 0, -1], "radius": 0.5}]})");
  const Result r = sphray::test::run_sphray_on_terminal("render -s " + path("s.json") +
                                                        " -W 8 -H 8 -o " + path("s.png"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("reading " + path("s.json")), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("building the tree"), std::string::npos) << r.out;  // 1 sphere: none
  const Result quiet =
      sphray::test::run_sphray_on_terminal("render -s random:300 -W 8 -H 8 -q -o " + path("q.png"));
  EXPECT_EQ(quiet.status, 0) << quiet.out;
  EXPECT_EQ(quiet.out, "");
}

// stderr a pipe: no bar and no control characters; a run this short prints only the summary.
TEST_F(Cli, ProgressWhenNotATerminalIsPlainLines) {
  const Result r = run("render -s random:300 -m path -W 16 -H 16 -o " + path("p.png"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out.find('\r'), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find('\033'), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find('['), std::string::npos) << r.out;
  EXPECT_EQ(r.out.rfind("wrote ", 0), 0u) << r.out;
}

// The second summary line: where the time went and the peak memory. Checked against what must
// be true whatever the machine: the phases fit in the total, and the peak holds at least the
// spheres themselves (16 bytes each), so a unit slip (kilobytes for bytes) fails.
TEST_F(Cli, SummaryShowsThePhasesAndThePeakMemory) {
  const Result r = run("render -s random:200000 -m normals -W 32 -H 32 -o " + path("m.png"));
  ASSERT_EQ(r.status, 0) << r.out;
  const std::size_t at = r.out.find("phases: ");
  ASSERT_NE(at, std::string::npos) << r.out;
  double scene = 0, tree = 0, render = 0, write = 0, total = 0, mb = 0, per_sphere = 0;
  ASSERT_EQ(std::sscanf(r.out.c_str() + at,
                        "phases: scene %lf s, tree %lf s, render %lf s, write %lf s; first image "
                        "in %lf s; peak memory %lf MB (%lf bytes per sphere)",
                        &scene, &tree, &render, &write, &total, &mb, &per_sphere),
            7)
      << r.out;
  EXPECT_GT(tree, 0.0) << r.out;  // 200,000 spheres: a tree
  EXPECT_LE(scene + tree + render + write, total + 0.002) << r.out;
  EXPECT_GE(mb * 1e6, 200000.0 * 16) << r.out;
  EXPECT_NEAR(per_sphere, mb * 1e6 / 200000, 0.1 + 1e-3 * per_sphere) << r.out;
}

namespace progress = sphray::render::progress;

// One unit for every rate, the summary's and the bar's: small rates get more decimals, not
// another unit.
TEST(ProgressText, RatesAreAlwaysInMraysPerSecond) {
  EXPECT_EQ(progress::rate_text(70), "0.000070 Mrays/s");
  EXPECT_EQ(progress::rate_text(123456), "0.123 Mrays/s");
  EXPECT_EQ(progress::rate_text(12.3456e6), "12.35 Mrays/s");
  EXPECT_EQ(progress::rate_text(0), "0.00 Mrays/s");
}

TEST(ProgressText, Durations) {
  EXPECT_EQ(progress::duration_text(0.42), "0.4 s");
  EXPECT_EQ(progress::duration_text(12.4), "12 s");
  EXPECT_EQ(progress::duration_text(125), "2 min 05 s");
  EXPECT_EQ(progress::duration_text(3720), "1 h 02 min");
}

// The rate and the time left come from the tracing alone: a long tree build before it (here
// 100 s of the 104 elapsed) changes neither.
TEST(ProgressText, RateAndTimeLeftCountOnlyTheTracing) {
  progress::Snapshot s;
  s.phase = "building the tree of 8000000 spheres";
  s.elapsed = 3.21;
  EXPECT_EQ(progress::terminal_line(s), "building the tree of 8000000 spheres ... 3.2 s elapsed");
  EXPECT_EQ(progress::log_line(s), "sphray: building the tree of 8000000 spheres, 3.2 s elapsed");
  EXPECT_LT(progress::seconds_left(s), 0);  // not rendering yet: unknown
  s.phase = "rendering";
  s.rendering = true;
  s.elapsed = 104;
  s.trace_seconds = 4;
  s.done = 45;
  s.total = 100;
  s.rays = {9000000, 0, 0};
  EXPECT_NEAR(progress::seconds_left(s), 4.0 * 55 / 45, 1e-9);
  EXPECT_EQ(progress::terminal_line(s),
            "rendering [##########              ]  45% 9.0M camera rays, 2.25 Mrays/s, about 4.9 s "
            "left, 1 min 44 s elapsed");
  EXPECT_EQ(progress::log_line(s),
            "sphray: rendering: 45%, 9.0M camera rays, 2.25 Mrays/s, about 4.9 s left, 1 min 44 s "
            "elapsed");
  s.time_limit = 6;  // path mode stops starting samples after 6 s of tracing
  EXPECT_NEAR(progress::seconds_left(s), 2.0, 1e-9);
}

TEST_F(Cli, ScenesInfoAndHelp) {
  Result scenes = run("scenes");
  EXPECT_EQ(scenes.status, 0);
  for (const char* name : {"single", "three", "rtiow-final", "random:N"}) {
    EXPECT_NE(scenes.out.find(name), std::string::npos) << name;
  }
  Result info = run("info");
  EXPECT_EQ(info.status, 0);
  EXPECT_NE(info.out.find("instruction set: "), std::string::npos) << info.out;
  // The trees' line runs from the smallest tree's instruction set to that of many spheres.
  const std::size_t trees = info.out.find("trees: ");
  ASSERT_NE(trees, std::string::npos) << info.out;
  const std::size_t end = info.out.find('\n', trees);
  const std::string line = info.out.substr(trees + 7, end - trees - 7);
  const std::string smallest(sphray::isa_name(sphray::bvh_isa(0)));
  const std::string many(sphray::isa_name(sphray::bvh_isa()));
  EXPECT_EQ(line.substr(0, smallest.size()), smallest) << line;
  EXPECT_EQ(line.substr(line.size() - std::min(line.size(), many.size())), many) << line;
  for (const char* help : {"--help", "render --help", "scenes --help", "info --help"}) {
    Result r = run(help);
    EXPECT_EQ(r.status, 0) << help;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << help << ": " << r.out;
  }
  EXPECT_NE(run("render --help").out.find("--spp"), std::string::npos);
}

// Every refusal: the status, the one line it prints, and the existing output untouched.
struct Refusal {
  std::string name;   // the test's name
  std::string args;   // before -o
  std::string scene;  // written to bad.json when not empty
  int status;
  std::string message;  // the whole line, with DIR standing for the test's folder
};

class CliRefusals : public Cli, public ::testing::WithParamInterface<Refusal> {};

void PrintTo(const Refusal& refusal, std::ostream* out) {
  *out << refusal.args;
}

TEST_P(CliRefusals, ExitStatusMessageAndOutputUntouched) {
  const Refusal& refusal = GetParam();
  std::string output = path("out.png");
  std::string original = "not really a PNG, but it must survive";
  write_text(output, original);
  if (!refusal.scene.empty()) write_text(path("bad.json"), refusal.scene);
  auto expand = [&](std::string text) {
    for (std::size_t at; (at = text.find("DIR")) != std::string::npos;) {
      text.replace(at, 3, dir_.string());
    }
    return text;
  };
  std::string args = expand(refusal.args);
  if (args.starts_with("render") && args.find(" -o ") == std::string::npos) {
    args += " -o " + output;
  }
  Result r = run(args);
  EXPECT_EQ(r.status, refusal.status) << r.out;
  EXPECT_EQ(r.out, expand(refusal.message) + "\n");
  EXPECT_EQ(read_bytes(output), original);
  EXPECT_EQ(files_in_dir(), refusal.scene.empty() ? 1u : 2u);  // no temporary file left
}

const char kSphere[] = R"({"center": [0, 0, -1], "radius": 0.5})";

INSTANTIATE_TEST_SUITE_P(
    BadInput, CliRefusals,
    ::testing::Values(
        Refusal{"UnknownExtension", "render -s single -o DIR/out.bmp", "", 2,
                "sphray: DIR/out.bmp: expected an output file ending in .png or .ppm"},
        Refusal{"UnknownPreset", "render -s nosuch", "", 2,
                "sphray: nosuch: expected a preset (single, three, rtiow-final, random:N) or a "
                ".json file"},
        Refusal{"RandomZero", "render -s random:0", "", 2,
                "sphray: random:0: expected random:N with N from 1 to 16777216"},
        Refusal{"SceneNotFound", "render -s DIR/missing.json", "", 2,
                "sphray: DIR/missing.json: cannot read the scene file (No such file or "
                "directory)"},
        Refusal{"SceneIsADirectory", "render -s DIR", "", 2,
                "sphray: DIR: expected a scene file, got a directory"},
        Refusal{"EmptyFile", "render -s DIR/bad.json", "\n  \n", 2,
                "sphray: DIR/bad.json: expected a JSON scene, the file is empty"},
        Refusal{"NotJson", "render -s DIR/bad.json", "spheres: []", 2,
                "sphray: DIR/bad.json:1:1: expected valid JSON (syntax error while parsing value "
                "- invalid literal; last read: 's')"},
        Refusal{"MissingField", "render -s DIR/bad.json", "{\"spheres\": [{\"radius\": 1}]}", 2,
                "sphray: DIR/bad.json:1:14: expected a sphere to have a \"center\""},
        Refusal{"MistypedField", "render -s DIR/bad.json",
                "{\"spheres\": [{\"center\": [0,0,-1], \"radius\": \"1\"}]}", 2,
                "sphray: DIR/bad.json:1:45: expected \"radius\" to be a number, got a string"},
        Refusal{"NaN", "render -s DIR/bad.json",
                "{\"spheres\": [{\"center\": [0,NaN,-1], \"radius\": 1}]}", 2,
                "sphray: DIR/bad.json:1:28: expected valid JSON (syntax error while parsing value "
                "- invalid literal; last read: '0,N')"},
        Refusal{"NegativeRadius", "render -s DIR/bad.json",
                "{\"spheres\": [\n  {\"center\": [0,0,-1], \"radius\": -0.5}\n]}", 2,
                "sphray: DIR/bad.json:2:34: expected \"radius\" to be positive, got -0.5"},
        Refusal{"UnknownKey", "render -s DIR/bad.json",
                std::string("{\"spheres\": [") + kSphere + "], \"lights\": []}", 2,
                "sphray: DIR/bad.json:1:54: expected one of the keys name, camera, spheres, "
                "width, height, sky in the scene, got unknown key \"lights\""},
        Refusal{"UnknownMaterial", "render -s DIR/bad.json",
                "{\"spheres\": [\n  {\"center\": [0,0,-1], \"radius\": 0.5, \"material\": "
                "{\"type\": \"plastic\"}}\n]}",
                2,
                "sphray: DIR/bad.json:2:60: expected \"type\" to be \"lambertian\", \"metal\" or "
                "\"dielectric\", got \"plastic\""},
        Refusal{"AlbedoAboveOne", "render -s DIR/bad.json",
                "{\"spheres\": [{\"center\": [0,0,-1], \"radius\": 0.5, \"material\": "
                "{\"type\": \"metal\", \"albedo\": [1, 1.01, 1]}}]}",
                2, "sphray: DIR/bad.json:1:94: expected \"albedo\" components in [0, 1]"},
        Refusal{"NegativeFuzz", "render -s DIR/bad.json",
                "{\"spheres\": [{\"center\": [0,0,-1], \"radius\": 0.5, \"material\": "
                "{\"type\": \"metal\", \"fuzz\": -1}}]}",
                2, "sphray: DIR/bad.json:1:88: expected \"fuzz\" in [0, 1], got -1"},
        Refusal{"ZeroIor", "render -s DIR/bad.json",
                "{\"spheres\": [{\"center\": [0,0,-1], \"radius\": 0.5, \"material\": "
                "{\"type\": \"dielectric\", \"ior\": 0}}]}",
                2, "sphray: DIR/bad.json:1:92: expected \"ior\" to be positive, got 0"},
        Refusal{"NaNIor", "render -s DIR/bad.json",
                "{\"spheres\": [{\"center\": [0,0,-1], \"radius\": 0.5, \"material\": "
                "{\"type\": \"dielectric\", \"ior\": NaN}}]}",
                2,
                "sphray: DIR/bad.json:1:92: expected valid JSON (syntax error while parsing value "
                "- invalid literal; last read: '\"ior\": N')"},
        Refusal{"ZeroMaxDepth", "render -m path --max-depth 0", "", 2,
                "sphray: --max-depth: Value 0 not in range 1 to 10000 (see sphray --help)"},
        Refusal{"NegativeTimeLimit", "render -m path --time-limit -1", "", 2,
                "sphray: --time-limit: expected seconds from 0 to 1e9, got -1 (see sphray --help)"},
        Refusal{"NaNTimeLimit", "render -m path --time-limit nan", "", 2,
                "sphray: --time-limit: expected seconds from 0 to 1e9, got nan (see sphray "
                "--help)"},
        Refusal{"UnknownMode", "render -m glossy", "", 2,
                "sphray: --mode: glossy not in {normals,flat,depth,id,shaded,path} (see sphray "
                "--help)"},
        Refusal{"UnknownAccel", "render --accel kd-tree", "", 2,
                "sphray: --accel: kd-tree not in {auto,bvh,brute} (see sphray --help)"},
        Refusal{"ZeroWidth", "render -W 0", "", 2,
                "sphray: --width: Value 0 not in range 1 to 16384 (see sphray --help)"},
        Refusal{"NotANumber", "render --spp lots", "", 2,
                "sphray: --spp: Value lots not in range 1 to 65536 (see sphray --help)"},
        Refusal{"UnknownOption", "render --frobnicate", "", 2,
                "sphray: The following argument was not expected: --frobnicate (see sphray "
                "--help)"},
        Refusal{"UnknownCommand", "paint", "", 2,
                "sphray: The following argument was not expected: paint (see sphray --help)"},
        Refusal{"UnwritableOutput", "render -s single -o DIR/no/such/folder/out.png", "", 1,
                "sphray: DIR/no/such/folder/out.png: cannot create the output file (No such "
                "file or directory)"}),
    [](const auto& info) { return info.param.name; });

}  // namespace
