// `quack run` called directly (apps/quack/run.hpp): outputs checked before anything runs,
// written all or nothing, temporaries removed on failure and on signals, state files a
// pure function of the scene, progress and size budgets on big scenes.

#include "run.hpp"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cctype>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "quack/io/state.hpp"

namespace quack::app {
namespace {

// True when `err` has "step 1/2 (50%), RATE," with RATE one of "240 steps/s",
// "2.5 steps/s" or "3.2 s/step" (digits, an optional one-digit fraction, the unit).
bool rateReads(const std::string& err) {
  const std::string head = "step 1/2 (50%), ";
  for (std::size_t at = err.find(head); at != std::string::npos; at = err.find(head, at + 1)) {
    std::size_t i = at + head.size();
    const std::size_t digits = i;
    while (i < err.size() && std::isdigit(static_cast<unsigned char>(err[i])) != 0)
      ++i;
    if (i == digits) continue;
    bool fraction = false;
    if (i + 1 < err.size() && err[i] == '.' &&
        std::isdigit(static_cast<unsigned char>(err[i + 1])) != 0) {
      fraction = true;
      i += 2;
    }
    const std::string rest = err.substr(i, 12);
    if (rest.rfind(" steps/s,", 0) == 0) return true;
    if (fraction && rest.rfind(" s/step,", 0) == 0) return true;
  }
  return false;
}

namespace fs = std::filesystem;
const fs::path kSource = QUACK_SOURCE_DIR;

// A fresh folder per test, removed after.
class Run : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("quack_run_test_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string at(const std::string& name) const { return (dir_ / name).string(); }

  RunOptions options(const std::string& scene = "pyramid.json", std::uint64_t steps = 5) const {
    RunOptions o;
    o.scene = (kSource / "scenes" / scene).string();
    o.steps = steps;
    o.out = at("state.json");
    o.quiet = true;
    return o;
  }

  int run(const RunOptions& o) {
    out_.str("");
    err_.str("");
    return runScene(o, out_, err_);
  }

  // `scene` run 90 steps in one go (straight.json, straight.jsonl), 40 steps with a run
  // snapshot at step 40 (40.snap), and from that snapshot on to 90 (resumed.json,
  // resumed.jsonl).
  void runStraightAndResumed(const std::string& scene) {
    RunOptions straight = options(scene, 90);
    straight.out = at("straight.json");
    straight.events = at("straight.jsonl");
    ASSERT_EQ(run(straight), kRunOk) << err_.str();
    RunOptions first = options(scene, 40);
    first.out = at("first.json");
    first.snapshotAt = 40;
    first.snapshotFile = at("40.snap");
    ASSERT_EQ(run(first), kRunOk) << err_.str();
    RunOptions resumed = options(scene, 90);
    resumed.out = at("resumed.json");
    resumed.resume = at("40.snap");
    resumed.events = at("resumed.jsonl");
    ASSERT_EQ(run(resumed), kRunOk) << err_.str();
  }

  // The event lines after step `step`: from the first whose step number is above it (empty
  // when there is none).
  static std::string linesAfterStep(const std::string& events, unsigned long step) {
    const std::string head = "{\"step\": ";
    for (std::size_t line = 0; line < events.size();) {
      if (events.compare(line, head.size(), head) == 0 &&
          std::stoul(events.substr(line + head.size())) > step)
        return events.substr(line);
      const std::size_t end = events.find('\n', line);
      if (end == std::string::npos) break;
      line = end + 1;
    }
    return {};
  }

  // Every file in the folder, recursively, that is a temporary (".part").
  std::vector<std::string> temporaries() const {
    std::vector<std::string> found;
    for (const auto& e : fs::recursive_directory_iterator(dir_)) {
      if (e.path().filename().string().find(".part") != std::string::npos)
        found.push_back(e.path().string());
    }
    return found;
  }

  static std::string read(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  static void write(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
  }

  fs::path dir_;
  std::ostringstream out_, err_;
};

// Issue 9: `--out DIR` simulated the whole run, then failed and left `DIR.part`.
TEST_F(Run, OutIsADirectoryIsRefusedBeforeLoadingAndLeavesNothing) {
  fs::create_directory(at("dir"));
  RunOptions o = options();
  o.out = at("dir");
  std::vector<std::string> phases;
  o.onPhase = [&](const std::string& p) { phases.push_back(p); };
  EXPECT_EQ(run(o), kRunFailed);
  EXPECT_TRUE(phases.empty()) << "it began " << phases.front();
  EXPECT_NE(err_.str().find("--out " + at("dir") + ": is a directory"), std::string::npos)
      << err_.str();
  EXPECT_TRUE(temporaries().empty());
  EXPECT_TRUE(fs::is_directory(at("dir")));
}

// Issue 9: `--out x --svg x` exited 0 with the state file lost under the SVG. Outputs must
// be distinct after normalisation, and none may be the scene.
TEST_F(Run, TheSameFileTwiceOrTheSceneAsOutputIsRefused) {
  fs::create_directory(at("sub"));
  RunOptions o = options();
  o.out = at("x");
  o.svg = at("sub/../x");
  EXPECT_EQ(run(o), kRunFailed);
  EXPECT_NE(err_.str().find("is the same file as --out"), std::string::npos) << err_.str();
  o.svg = at("y.svg");
  o.html = at("./y.svg");
  EXPECT_EQ(run(o), kRunFailed);
  EXPECT_NE(err_.str().find("--html " + at("./y.svg") + ": is the same file as --svg"),
            std::string::npos)
      << err_.str();
  // A symbolic link to another output is the same file too.
  fs::create_symlink(at("x"), at("link"));
  o.html = at("link");
  EXPECT_EQ(run(o), kRunFailed);
  EXPECT_NE(err_.str().find("is the same file as --out"), std::string::npos) << err_.str();
  // The scene itself, under another spelling.
  write(at("scene.json"), read((kSource / "scenes/pyramid.json").string()));
  o = options();
  o.scene = at("scene.json");
  o.timing = at("sub/../scene.json");
  EXPECT_EQ(run(o), kRunFailed);
  EXPECT_NE(err_.str().find("is the scene file"), std::string::npos) << err_.str();
  EXPECT_EQ(read(at("scene.json")), read((kSource / "scenes/pyramid.json").string()));
  EXPECT_FALSE(fs::exists(at("x")));
  EXPECT_FALSE(fs::exists(at("state.json")));
  EXPECT_TRUE(temporaries().empty());
}

// Issue 12: "cannot write PATH" gave no reason.
TEST_F(Run, AnOutputThatCannotBeWrittenSaysWhy) {
  RunOptions o = options();
  o.svg = at("no/such/folder/x.svg");
  EXPECT_EQ(run(o), kRunFailed);
  EXPECT_NE(err_.str().find("--svg " + at("no/such/folder/x.svg") + ": cannot write: the folder " +
                            at("no/such/folder") + " does not exist"),
            std::string::npos)
      << err_.str();
  o.svg = "/dev/null";
  EXPECT_EQ(run(o), kRunFailed);
  EXPECT_NE(err_.str().find("is not a regular file"), std::string::npos) << err_.str();
}

// Issue 9: a full disk while writing the replay left the state file already replaced and a
// `.part` behind. A file size limit (RLIMIT_FSIZE) makes the disk "full" for a child
// process: the state file fits, the replay does not.
TEST_F(Run, FullDiskWhileWritingTheReplayChangesNoOutputAndLeavesNoTemporary) {
  write(at("state.json"), "previous state\n");
  write(at("last.svg"), "previous svg\n");
  pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    std::signal(SIGXFSZ, SIG_IGN);  // a write past the limit fails with EFBIG instead
    rlimit limit{200000, 200000};
    setrlimit(RLIMIT_FSIZE, &limit);
    RunOptions o = options("pyramid.json", 30);
    o.svg = at("last.svg");
    o.html = at("replay.html");
    std::ostringstream out, err;
    int rc = runScene(o, out, err);
    std::ofstream(at("child.err")) << err.str();
    _exit(rc);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), kRunFailed);
  std::string err = read(at("child.err"));
  EXPECT_NE(err.find("writing " + at("replay.html") + " failed: File too large"), std::string::npos)
      << err;
  EXPECT_EQ(read(at("state.json")), "previous state\n");
  EXPECT_EQ(read(at("last.svg")), "previous svg\n");
  EXPECT_FALSE(fs::exists(at("replay.html")));
  EXPECT_TRUE(temporaries().empty());
}

// Issue 9: Ctrl-C left empty `.part` files. A signal while the temporaries exist (here
// raised the moment all are complete, before any rename) removes them and exits 130
// (SIGINT) or 143 (SIGTERM); the previous outputs stay.
TEST_F(Run, SignalWhileWritingRemovesTemporariesAndExits130Or143) {
  for (int sig : {SIGINT, SIGTERM}) {
    SCOPED_TRACE(sig);
    write(at("state.json"), "previous state\n");
    RunOptions o = options();
    o.svg = at("last.svg");
    o.html = at("replay.html");
    o.timing = at("timing.json");
    bool sawTemporaries = false;
    o.onPhase = [&](const std::string& p) {
      if (p != "commit") return;
      sawTemporaries = temporaries().size() == 4;
      std::raise(sig);
    };
    EXPECT_EQ(run(o), sig == SIGINT ? kRunInterrupted : kRunTerminated);
    EXPECT_TRUE(sawTemporaries);
    EXPECT_TRUE(temporaries().empty());
    EXPECT_EQ(read(at("state.json")), "previous state\n");
    EXPECT_FALSE(fs::exists(at("last.svg")));
    EXPECT_FALSE(fs::exists(at("replay.html")));
    EXPECT_FALSE(fs::exists(at("timing.json")));
  }
  // A signal between steps stops the simulation there; nothing is written.
  RunOptions o = options("pyramid.json", 1000000);
  o.onPhase = [](const std::string& p) {
    if (p == "simulate") std::raise(SIGTERM);
  };
  EXPECT_EQ(run(o), kRunTerminated);
  EXPECT_EQ(read(at("state.json")), "previous state\n");
  EXPECT_TRUE(temporaries().empty());
  // The handlers are put back: this process still has its own.
  struct sigaction now {};
  sigaction(SIGINT, nullptr, &now);
  EXPECT_EQ(now.sa_handler, SIG_DFL);
}

// --threads: the state file is the same to the byte on any number of workers, and the
// summary and timing file say how many ran (docs/world.md, "Threads").
TEST_F(Run, ThreadsChangeNothingButTheSpeed) {
  RunOptions o = options("rain.json", 90);
  o.threads = 1;
  ASSERT_EQ(run(o), kRunOk) << err_.str();
  const std::string one = read(at("state.json"));
  EXPECT_NE(out_.str().find(", 1 thread)"), std::string::npos) << out_.str();
  for (int threads : {2, 3}) {
    out_.str("");
    o.threads = threads;
    o.out = at("state" + std::to_string(threads) + ".json");
    o.timing = at("timing" + std::to_string(threads) + ".json");
    ASSERT_EQ(run(o), kRunOk) << err_.str();
    EXPECT_EQ(read(o.out), one) << threads << " threads";
    EXPECT_NE(out_.str().find(", " + std::to_string(threads) + " threads)"), std::string::npos)
        << out_.str();
    EXPECT_NE(read(o.timing).find("\"threads\": " + std::to_string(threads)), std::string::npos);
  }
}

// Issue 14: `timing` made two identical runs' state files differ. The state file is a pure
// function of the scene and the step count; timing goes to the summary and `--timing`.
TEST_F(Run, TwoRunsWriteByteIdenticalStateFilesAndTimingGoesElsewhere) {
  RunOptions o = options("rain.json", 60);
  o.timing = at("timing.json");
  ASSERT_EQ(run(o), kRunOk) << err_.str();
  std::string first = read(at("state.json"));
  EXPECT_NE(out_.str().find("ms/step"), std::string::npos);
  EXPECT_NE(out_.str().find("timing    " + at("timing.json")), std::string::npos);
  std::string timing = read(at("timing.json"));
  for (const char* key : {"\"ms_per_step\"", "\"steps_per_s\"", "\"load_ms\"", "\"build_ms\"",
                          "\"simulate_ms\"", "\"render_ms\"", "\"write_ms\""})
    EXPECT_NE(timing.find(key), std::string::npos) << key;
  o.timing.clear();
  o.out = at("again.json");
  ASSERT_EQ(run(o), kRunOk) << err_.str();
  EXPECT_EQ(read(at("again.json")), first);
  EXPECT_EQ(first.find("timing"), std::string::npos);
}

// Issue 19: the event list (--events) is written beside the state, one line per event,
// agrees with the state file's totals, and two runs write the same bytes.
TEST_F(Run, EventListAgreesWithTheTotalsAndRepeatsByteForByte) {
  RunOptions o = options("bullets.json", 120);
  o.events = at("events.jsonl");
  ASSERT_EQ(run(o), kRunOk) << err_.str();
  EXPECT_NE(out_.str().find("event log " + at("events.jsonl")), std::string::npos) << out_.str();
  const std::string events = read(at("events.jsonl"));
  Result<StateFile> state = parseState(read(at("state.json")), "state.json");
  ASSERT_TRUE(state.ok()) << state.error().message;
  auto count = [&](const std::string& kind) {
    std::size_t n = 0;
    const std::string key = "\"event\": \"" + kind + "\"";
    for (std::size_t pos = events.find(key); pos != std::string::npos;
         pos = events.find(key, pos + 1))
      ++n;
    return n;
  };
  EXPECT_EQ(count("begin"), state->events.begin);
  EXPECT_EQ(count("end"), state->events.end);
  EXPECT_EQ(count("hit"), state->events.hit);
  EXPECT_EQ(count("sensor-begin"), state->events.sensor);
  EXPECT_GT(count("toi"), 0u);  // the bullets reach the walls through the continuous phase
  EXPECT_GT(state->events.begin, 0u);
  // Every line is a JSON object with a step number.
  std::istringstream lines(events);
  std::size_t n = 0;
  for (std::string line; std::getline(lines, line); ++n)
    ASSERT_EQ(line.rfind("{\"step\": ", 0), 0u) << line;
  EXPECT_GT(n, 0u);
  o.out = at("again.json");
  o.events = at("again.jsonl");
  ASSERT_EQ(run(o), kRunOk) << err_.str();
  EXPECT_EQ(read(at("again.jsonl")), events);
}

// Hardening round 2, item 3: a resumed run's event lines numbered steps from 1 after the
// snapshot. The resumed lines must be the straight run's lines from the snapshot on, byte for
// byte, step numbers counted from the scene's start.
TEST_F(Run, ResumedEventLinesCountStepsFromTheScenesStart) {
  ASSERT_NO_FATAL_FAILURE(runStraightAndResumed("concave.json"));
  const std::string after = linesAfterStep(read(at("straight.jsonl")), 40);
  const std::string tail = read(at("resumed.jsonl"));
  ASSERT_FALSE(tail.empty());
  ASSERT_FALSE(after.empty()) << "no event after step 40 in the straight run";
  EXPECT_EQ(after, tail);
  EXPECT_EQ(tail.find("{\"step\": 1,"), std::string::npos);
}

// Hardening round 2, item 4: the event totals (bytes 12-43) were outside every checksum, so a
// flipped bit went into the state file. Every byte of the header is now covered: flipping any
// bit of bytes 8-51 (version, totals, checksum) is refused with exit 2 and writes nothing.
TEST_F(Run, AFlippedBitInTheRunSnapshotHeaderIsRefused) {
  RunOptions first = options("pyramid.json", 20);
  first.snapshotAt = 20;
  first.snapshotFile = at("20.snap");
  ASSERT_EQ(run(first), kRunOk) << err_.str();
  const std::string good = read(at("20.snap"));
  ASSERT_GT(good.size(), 52u);
  int refused = 0;
  for (std::size_t byte = 8; byte < 52; ++byte) {
    for (int bit : {0, 7}) {
      std::string bad = good;
      bad[byte] = static_cast<char>(bad[byte] ^ (1 << bit));
      write(at("bad.snap"), bad);
      RunOptions o = options("pyramid.json", 30);
      o.out = at("bad.json");
      o.resume = at("bad.snap");
      ASSERT_EQ(run(o), kRunFailed) << "byte " << byte << " bit " << bit;
      EXPECT_FALSE(fs::exists(at("bad.json")));
      ++refused;
    }
  }
  EXPECT_EQ(refused, 88);
  // The good file still resumes.
  RunOptions o = options("pyramid.json", 30);
  o.resume = at("20.snap");
  EXPECT_EQ(run(o), kRunOk) << err_.str();
}

// Hardening round 2, item 7: --resume /dev/zero read the whole (endless) input before
// checking the magic bytes, and ran out of memory. The header is checked first.
TEST_F(Run, ResumeFromAnEndlessStreamIsRefusedByItsHeader) {
  RunOptions o = options("pyramid.json", 10);
  o.resume = "/dev/zero";
  ASSERT_EQ(run(o), kRunFailed);
  EXPECT_NE(err_.str().find("not a quack run snapshot"), std::string::npos) << err_.str();
}

// Hardening round 2, item 11: a 0.1 mm box sank 88% of its size and a 1 um box fell through
// a 2 um ground, silently. A scene with moving shapes thinner than 1 cm (twice the 5 mm
// slop) runs, with one warning naming the thinnest; the sample pyramid gets none.
TEST_F(Run, MovingShapesThinnerThanTheSlopGetAWarning) {
  write(at("tiny.json"), R"({"bodies": [
    {"name": "ground", "type": "static", "pos": [0, -1], "shapes": [{"type": "box", "half": [5, 1]}]},
    {"name": "speck", "pos": [0, 0.5], "shapes": [{"type": "box", "half": [0.00005, 0.00005]}]},
    {"name": "chip", "pos": [1, 0.5], "shapes": [{"type": "circle", "radius": 0.004}]},
    {"name": "ball", "pos": [2, 0.5], "shapes": [{"type": "circle", "radius": 0.5}]}]})");
  RunOptions o = options("pyramid.json", 3);
  o.scene = at("tiny.json");
  ASSERT_EQ(run(o), kRunOk) << err_.str();
  EXPECT_NE(err_.str().find("warning: 2 moving shapes are thinner than 1 cm (the thinnest, on "
                            "body \"speck\", is 0.0001 m)"),
            std::string::npos)
      << err_.str();
  ASSERT_EQ(run(options("pyramid.json", 3)), kRunOk);
  EXPECT_EQ(err_.str().find("warning"), std::string::npos) << err_.str();
}

// Issue 15: 10^6 bodies gave no progress while building and writing, and "0 steps/s".
// A big generated scene (kept fast: two steps) reports every phase on stderr, with a rate
// in s/step when steps are slow, and its SVG and replay stay within their size budgets
// (docs/scenes.md, "Size budgets") while drawing a sample of the shapes.
TEST_F(Run, LargeGeneratedSceneShowsProgressAndStaysWithinSizeBudgets) {
  write(at("big.json"), R"({"bodies": [{"name": "ground", "type": "static", "pos": [0, -1],
      "shapes": [{"type": "box", "half": [400, 1]}]}],
      "generate": [{"kind": "rain", "count": 40000, "pos": [0, 100], "size": [390, 95]}]})");
  RunOptions o = options();
  o.scene = at("big.json");
  o.steps = 2;
  o.quiet = false;
  o.progressAfter = 0.0;
  o.svg = at("big.svg");
  o.html = at("big.html");
  o.htmlBoxes = true;
  ASSERT_EQ(run(o), kRunOk) << err_.str();
  EXPECT_LE(fs::file_size(at("big.svg")), std::uintmax_t{16} << 20);
  EXPECT_LE(fs::file_size(at("big.html")), std::uintmax_t{32} << 20);
  EXPECT_NE(read(at("big.svg")).find("of 40001 shapes"), std::string::npos);
  EXPECT_NE(out_.str().find("of 40001 shapes drawn"), std::string::npos) << out_.str();
  EXPECT_NE(out_.str().find("bodies    40001"), std::string::npos) << out_.str();
  // Progress: every phase (shown from the start here: progressAfter 0).
  const std::string err = err_.str();
  for (const char* line : {"quack run: loading: ", "quack run: building the world: 40001 bodies",
                           "quack run: simulating: 2 steps", "quack run: simulating: step 1/2",
                           "quack run: rendering: the state file", "quack run: rendering: the SVG",
                           "quack run: rendering: the replay", "quack run: writing: "})
    EXPECT_NE(err.find(line), std::string::npos) << line << " in\n" << err;
  // The rate reads at any speed: "240 steps/s", "2.5 steps/s" or "3.2 s/step".
  // (Checked by hand rather than with std::regex: GCC 12 warns falsely inside <regex> at -O2
  // with the sanitizers.)
  EXPECT_TRUE(rateReads(err)) << err;
  EXPECT_EQ(err.find(" 0 steps/s"), std::string::npos) << err;
  EXPECT_EQ(err.find(" 0.0 s/step"), std::string::npos) << err;
}

// ---- 3D scenes ----------------------------------------------------------------------------

// A 3D scene runs: the state file (3D, read back), the event list (agreeing with the
// totals), the WebGL replay and the timing are written; the summary says it is 3D; two runs
// write the same state bytes.
TEST_F(Run, A3DSceneWritesItsStateEventsAndReplay) {
  RunOptions o = options("hulls-3d.json", 90);
  o.threads = 1;
  o.events = at("events.jsonl");
  o.html = at("replay.html");
  o.timing = at("timing.json");
  std::vector<std::string> phases;
  o.onPhase = [&](const std::string& p) { phases.push_back(p); };
  ASSERT_EQ(run(o), kRunOk) << err_.str();
  EXPECT_EQ(phases,
            (std::vector<std::string>{"load", "build", "simulate", "render", "write", "commit"}));
  EXPECT_TRUE(err_.str().empty()) << err_.str();
  const std::string summary = out_.str();
  for (const char* line :
       {"hulls-3d.json (3D)", "bodies    49 (48 dynamic), 53 shapes",
        "steps     90 (1.500 s simulated", "events    begin ", "1 thread)", "replay    ", "WebGL"})
    EXPECT_NE(summary.find(line), std::string::npos) << line << "\n" << summary;
  const std::string text = read(at("state.json"));
  Result<StateFile3> state = parseState3(text, "state.json");
  ASSERT_TRUE(state.ok()) << state.error().message;
  EXPECT_EQ(state->steps, 90u);
  EXPECT_EQ(state->bodies.size(), 49u);
  EXPECT_EQ(state->bodies[1].name, "hull0");
  EXPECT_GT(state->events.begin, 0u);
  const std::string events = read(at("events.jsonl"));
  auto count = [&](const std::string& kind) {
    std::size_t n = 0;
    const std::string key = "\"event\": \"" + kind + "\"";
    for (std::size_t pos = events.find(key); pos != std::string::npos;
         pos = events.find(key, pos + 1))
      ++n;
    return n;
  };
  EXPECT_EQ(count("begin"), state->events.begin);
  EXPECT_EQ(count("end"), state->events.end);
  const std::string html = read(at("replay.html"));
  EXPECT_NE(html.find("getContext(\"webgl\""), std::string::npos);
  EXPECT_NE(read(at("timing.json")).find("\"steps\": 90"), std::string::npos);
  o.out = at("again.json");
  o.events.clear();
  o.html.clear();
  o.timing.clear();
  o.onPhase = {};
  ASSERT_EQ(run(o), kRunOk) << err_.str();
  EXPECT_EQ(read(at("again.json")), text);
}

// A 3D run stopped at a snapshot and resumed from it ends in the straight run's state file,
// and its event lines are the straight run's from the snapshot on (step numbers counted
// from the scene's start). A snapshot of another 3D scene, or of a step past --steps, is
// refused naming why, and writes nothing.
TEST_F(Run, A3DRunResumedFromItsSnapshotEndsAsTheStraightRun) {
  ASSERT_NO_FATAL_FAILURE(runStraightAndResumed("hulls-3d.json"));
  EXPECT_EQ(read(at("resumed.json")), read(at("straight.json")));
  const std::string after = linesAfterStep(read(at("straight.jsonl")), 40);
  const std::string tail = read(at("resumed.jsonl"));
  ASSERT_FALSE(tail.empty());
  ASSERT_FALSE(after.empty()) << "no event after step 40 in the straight run";
  EXPECT_EQ(after, tail);

  RunOptions other = options("cards-3d.json", 90);
  other.out = at("other.json");
  other.resume = at("40.snap");
  EXPECT_EQ(run(other), kRunFailed);
  EXPECT_NE(err_.str().find("the snapshot is of another scene"), std::string::npos) << err_.str();
  EXPECT_FALSE(fs::exists(at("other.json")));
  RunOptions early = options("hulls-3d.json", 30);
  early.out = at("early.json");
  early.resume = at("40.snap");
  EXPECT_EQ(run(early), kRunFailed);
  EXPECT_NE(err_.str().find("the snapshot is at step 40, after --steps 30"), std::string::npos)
      << err_.str();
  EXPECT_FALSE(fs::exists(at("early.json")));
}

// What the 3D world cannot do is refused before anything is built, naming the option, and
// writes nothing; --threads N runs it on N workers.
TEST_F(Run, A3DSceneRefusesWhatTheWorldLacksAndRunsOnAnyThreads) {
  struct Case {
    std::function<void(RunOptions&)> set;
    const char* message;
  };
  const Case cases[] = {
      {[this](RunOptions& o) { o.svg = at("last.svg"); }, "--svg: a 3D scene has no SVG picture"},
      {[this](RunOptions& o) {
         o.html = at("r.html");
         o.htmlBoxes = true;
       },
       "--html-boxes: the 3D replay does not draw the broad phase's boxes"},
  };
  for (const Case& c : cases) {
    RunOptions o = options("cards-3d.json", 5);
    c.set(o);
    std::vector<std::string> phases;
    o.onPhase = [&](const std::string& p) { phases.push_back(p); };
    EXPECT_EQ(run(o), kRunFailed) << c.message;
    EXPECT_NE(err_.str().find(c.message), std::string::npos) << err_.str();
    EXPECT_NE(err_.str().find("is a 3D scene"), std::string::npos) << err_.str();
    EXPECT_EQ(phases, std::vector<std::string>{"load"});
    EXPECT_FALSE(fs::exists(at("state.json")));
    EXPECT_TRUE(temporaries().empty());
  }
  // --threads N runs the 3D world on N workers, to the same state as one.
  RunOptions o = options("cards-3d.json", 5);
  o.threads = 1;
  ASSERT_EQ(run(o), kRunOk) << err_.str();
  const std::string one = read(at("state.json"));
  o.threads = 4;
  ASSERT_EQ(run(o), kRunOk) << err_.str();
  EXPECT_NE(out_.str().find(", 4 threads)"), std::string::npos) << out_.str();
  EXPECT_EQ(read(at("state.json")), one);
}

// A bad 3D scene exits 2 naming the file and the field, and writes nothing.
TEST_F(Run, ABad3DSceneNamesTheFieldAndWritesNothing) {
  write(at("bad-3d.json"),
        R"({"world": {"dim": 3}, "bodies": [{"quat": [0, 0, 0, 0], "shapes": []}]})");
  RunOptions o = options();
  o.scene = at("bad-3d.json");
  o.html = at("r.html");
  EXPECT_EQ(run(o), kRunFailed);
  EXPECT_NE(err_.str().find("bad-3d.json: bodies[0].quat: [0, 0, 0, 0] is not a rotation"),
            std::string::npos)
      << err_.str();
  EXPECT_FALSE(fs::exists(at("state.json")));
  EXPECT_FALSE(fs::exists(at("r.html")));
}

}  // namespace
}  // namespace quack::app
