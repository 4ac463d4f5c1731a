#include "run.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <iostream>
#include <optional>
#include <ostream>
#include <span>
#include <string_view>
#include <thread>
#include <utility>
#include <variant>
#include <vector>

#include "quack/core/assert.hpp"
#include "quack/geometry/bounds.hpp"
#include "quack/io/render.hpp"
#include "quack/io/render3.hpp"
#include "quack/io/scene.hpp"
#include "quack/io/scene3.hpp"
#include "quack/io/state.hpp"
#include "quack/world/tasks.hpp"

namespace quack::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// ---- signals -----------------------------------------------------------------------------

// Set by the handler, read between steps and between chunks of output: the handler does
// nothing else, so it is async-signal-safe; the run cleans up and returns 128 + signal.
volatile std::sig_atomic_t gSignal = 0;

extern "C" void onSignal(int sig) {
  gSignal = sig;
}

// Catches SIGINT and SIGTERM while a run is under way and puts the old handlers back after.
class SignalGuard {
 public:
  SignalGuard() {
    gSignal = 0;
    struct sigaction action {};
    action.sa_handler = onSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = 0;  // no SA_RESTART: a blocking write returns EINTR and we look
    sigaction(SIGINT, &action, &oldInt_);
    sigaction(SIGTERM, &action, &oldTerm_);
  }
  ~SignalGuard() {
    sigaction(SIGINT, &oldInt_, nullptr);
    sigaction(SIGTERM, &oldTerm_, nullptr);
  }
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;

 private:
  struct sigaction oldInt_ {};
  struct sigaction oldTerm_ {};
};

int interruptedStatus() {
  return gSignal == SIGTERM ? kRunTerminated : kRunInterrupted;
}

// ---- progress ----------------------------------------------------------------------------

std::string formatSeconds(double s) {
  char buf[48];
  if (s < 60.0) {
    std::snprintf(buf, sizeof buf, "%.1f s", s);
  } else if (s < 3600.0) {
    std::snprintf(buf, sizeof buf, "%d min %02d s", static_cast<int>(s / 60.0),
                  static_cast<int>(s) % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%d h %02d min", static_cast<int>(s / 3600.0),
                  static_cast<int>(s / 60.0) % 60);
  }
  return buf;
}

// Steps per second readable at any speed: "240 steps/s", "2.5 steps/s", "3.2 s/step".
std::string formatRate(double stepsPerSecond) {
  char buf[48];
  if (!(stepsPerSecond > 0.0)) return "no step yet";
  if (stepsPerSecond >= 10.0) {
    std::snprintf(buf, sizeof buf, "%.0f steps/s", stepsPerSecond);
  } else if (stepsPerSecond >= 1.0) {
    std::snprintf(buf, sizeof buf, "%.1f steps/s", stepsPerSecond);
  } else {
    std::snprintf(buf, sizeof buf, "%.1f s/step", 1.0 / stepsPerSecond);
  }
  return buf;
}

std::string formatBytes(std::size_t bytes) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.1f MB", static_cast<double>(bytes) / 1e6);
  return buf;
}

// Progress on stderr once a run has taken a second: from then on every phase says when
// it begins, then reports about once a second, and says how long it took. A line is
// rewritten in place on a terminal, whole lines otherwise. Short runs print nothing.
class Progress {
 public:
  Progress(std::ostream& err, bool enabled, double after)
      : err_(err),
        enabled_(enabled),
        after_(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(after))),
        tty_(&err == &std::cerr && isatty(STDERR_FILENO) != 0),
        runStart_(Clock::now()),
        last_(runStart_) {}

  // A new phase; `text` is shown at once if the run is already long.
  void begin(std::string phase, const std::string& text) {
    phase_ = std::move(phase);
    start_ = Clock::now();
    shown_ = false;
    if (enabled_ && start_ - runStart_ >= after_) {
      last_ = start_;
      show(text);
    }
  }
  double elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

  // `text()` is called only when a line is due.
  template <class Text>
  void update(Text&& text) {
    if (!enabled_) return;
    auto now = Clock::now();
    if (now - last_ < after_) return;
    last_ = now;
    show(text());
  }
  // Ends the phase with `text` if anything of it was shown.
  template <class Text>
  void end(Text&& text) {
    if (!enabled_ || !shown_) return;
    show(text());
    if (tty_) err_ << '\n' << std::flush;
  }

 private:
  void show(const std::string& text) {
    shown_ = true;
    std::string line = "quack run: " + phase_ + ": " + text;
    if (tty_) line += "\x1b[K";  // clear what a longer line left
    err_ << line << (tty_ ? "\r" : "\n") << std::flush;
  }

  std::ostream& err_;
  bool enabled_;
  Clock::duration after_;
  bool tty_;
  Clock::time_point runStart_, start_, last_;
  std::string phase_;
  bool shown_ = false;
};

// ---- outputs -----------------------------------------------------------------------------

// One output: where it goes (symbolic links followed), and its temporary file beside it.
struct Output {
  std::string option;  // "--out", for messages
  std::string path;    // as given
  fs::path target;     // resolved: the file to replace
  std::string temp;    // the temporary file, once created
  std::string text;
};

std::string errnoText(int e) {
  return std::strerror(e);
}

// The file a path ends at: absolute, `.` and `..` resolved, and symbolic links followed,
// dangling ones too (writing through a link to a file not yet made creates that file).
fs::path resolve(const std::string& path, std::error_code& ec) {
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  std::error_code missing;  // a path that does not exist yet is no link
  for (int hops = 0; !ec && hops < 40 && fs::is_symlink(fs::symlink_status(p, missing)); ++hops) {
    fs::path link = fs::read_symlink(p, ec);
    if (ec) break;
    p = fs::weakly_canonical(link.is_absolute() ? link : p.parent_path() / link, ec);
  }
  return p;
}

// Checks every output before anything is loaded: a path, distinct from every other output
// and from the scene after resolving `.`, `..` and symbolic links, not a directory or other
// non-file, in an existing folder this process may write in.
bool checkOutputs(std::vector<Output>& outputs, const std::string& scene, std::ostream& err) {
  std::error_code ec;
  fs::path scenePath = resolve(scene, ec);
  if (ec) scenePath.clear();
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    Output& o = outputs[i];
    auto bad = [&](const std::string& what) {
      err << "quack run: " << o.option << ' ' << o.path << ": " << what << '\n';
      return false;
    };
    if (o.path.empty()) return bad("is empty");
    ec.clear();
    o.target = resolve(o.path, ec);
    if (ec) return bad("cannot resolve the path: " + ec.message());
    if (o.target.filename().empty()) return bad("names a directory, not a file");
    fs::file_status st = fs::status(o.target, ec);
    if (fs::is_directory(st)) return bad("is a directory; name a file to write");
    if (fs::exists(st) && !fs::is_regular_file(st))
      return bad("exists and is not a regular file (a device, pipe or socket)");
    fs::path parent = o.target.parent_path();
    ec.clear();
    if (!fs::is_directory(parent, ec))
      return bad("cannot write: the folder " + parent.string() + " does not exist");
    if (access(parent.c_str(), W_OK | X_OK) != 0)
      return bad("cannot write in " + parent.string() + ": " + errnoText(errno));
    if (!scenePath.empty() && o.target == scenePath)
      return bad("is the scene file; writing it would destroy the scene");
    for (std::size_t k = 0; k < i; ++k) {
      bool same = outputs[k].target == o.target;
      if (!same && fs::exists(o.target, ec) && fs::exists(outputs[k].target, ec))
        same = fs::equivalent(o.target, outputs[k].target, ec);
      if (same) return bad("is the same file as " + outputs[k].option + ' ' + outputs[k].path);
    }
  }
  return true;
}

void removeTemps(std::vector<Output>& outputs) {
  for (Output& o : outputs) {
    if (!o.temp.empty()) unlink(o.temp.c_str());
    o.temp.clear();
  }
}

// Writes `o.text` to a new temporary file beside the target, in chunks, stopping at a
// signal; the file is flushed to disk (fsync) so that a full disk shows here, not later.
bool writeTemp(Output& o, Progress& progress, std::size_t& written, std::size_t total,
               std::ostream& err) {
  int fd = -1;
  for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
    o.temp =
        o.target.string() + ".part-" + std::to_string(getpid()) + "-" + std::to_string(attempt);
    fd = open(o.temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) {
    err << "quack run: cannot write " << o.path << ": " << errnoText(errno) << '\n';
    o.temp.clear();
    return false;
  }
  constexpr std::size_t kChunk = std::size_t{1} << 20;
  const char* data = o.text.data();
  std::size_t left = o.text.size();
  while (left > 0) {
    if (gSignal != 0) {
      close(fd);
      return false;
    }
    ssize_t n = write(fd, data, std::min(left, kChunk));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      int e = n < 0 ? errno : ENOSPC;
      close(fd);
      err << "quack run: writing " << o.path << " failed: " << errnoText(e) << '\n';
      return false;
    }
    data += n;
    left -= static_cast<std::size_t>(n);
    written += static_cast<std::size_t>(n);
    progress.update(
        [&] { return formatBytes(written) + " of " + formatBytes(total) + " (" + o.path + ")"; });
  }
  if (fsync(fd) != 0 && errno != EINVAL) {
    int e = errno;
    close(fd);
    err << "quack run: writing " << o.path << " failed: " << errnoText(e) << '\n';
    return false;
  }
  if (close(fd) != 0) {
    err << "quack run: writing " << o.path << " failed: " << errnoText(errno) << '\n';
    return false;
  }
  return true;
}

std::string timingJson(std::uint64_t steps, int threads, double loadMs, double buildMs,
                       double simulateMs, double renderMs, double writeMs) {
  char buf[512];
  double msPerStep = steps > 0 ? simulateMs / static_cast<double>(steps) : 0.0;
  std::snprintf(
      buf, sizeof buf,
      "{\n \"steps\": %llu,\n \"threads\": %d,\n \"ms_per_step\": %.6g,\n \"steps_per_s\": %.6g,\n"
      " \"load_ms\": %.6g,\n \"build_ms\": %.6g,\n \"simulate_ms\": %.6g,\n"
      " \"render_ms\": %.6g,\n \"write_ms\": %.6g\n}\n",
      static_cast<unsigned long long>(steps), threads, msPerStep,
      msPerStep > 0.0 ? 1000.0 / msPerStep : 0.0, loadMs, buildMs, simulateMs, renderMs, writeMs);
  return buf;
}

// A run snapshot: "QUACKRUN", a format version (u32), the event totals so far (four u64:
// begin, end, hit, sensor), a checksum (u64, FNV-1a of every byte before it), then the
// world's dynamic snapshot (World::snapshot), which carries its own checksum and is checked
// by World::restore (version, structure: the scene must be the one the snapshot was taken
// of). So every byte of the file is covered. Little-endian.
constexpr char kRunMagic[8] = {'Q', 'U', 'A', 'C', 'K', 'R', 'U', 'N'};
constexpr std::uint32_t kRunVersion = 2;
constexpr std::size_t kRunChecksumAt = 8 + 4 + 4 * 8;
constexpr std::size_t kRunHeader = kRunChecksumAt + 8;

std::uint64_t fnv1a(const char* data, std::size_t size) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (std::size_t i = 0; i < size; ++i) {
    h ^= static_cast<unsigned char>(data[i]);
    h *= 0x100000001b3ull;
  }
  return h;
}

std::string writeRunSnapshot(const EventTotals& totals, const std::vector<std::uint8_t>& world) {
  std::string out(kRunMagic, sizeof kRunMagic);
  auto put = [&](std::uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i)
      out.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
  };
  put(kRunVersion, 4);
  for (std::uint64_t v : {totals.begin, totals.end, totals.hit, totals.sensor})
    put(v, 8);
  put(fnv1a(out.data(), out.size()), 8);
  out.append(reinterpret_cast<const char*>(world.data()), world.size());
  return out;
}

// Reads a run snapshot file into the world and the totals; the message names the file.
// The header is read and checked before the rest, so that a file that is not a snapshot
// (or an endless one, /dev/zero) is refused without reading it whole.
// The world is a World or a World3 (its restore takes the rest of the file): the run
// snapshot's header is the same for 2D and 3D.
template <class AnyWorld>
Status readRunSnapshot(const std::string& path, AnyWorld& world, EventTotals& totals) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return fail(path + ": is a directory");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return fail(path + ": " + errnoText(errno));
  std::vector<std::uint8_t> bytes(kRunHeader);
  const std::size_t got = std::fread(bytes.data(), 1, kRunHeader, f);
  auto closed = [&](Status s) {
    std::fclose(f);
    return s;
  };
  if (std::ferror(f) != 0) return closed(fail(path + ": read error"));
  if (got < 8 || std::memcmp(bytes.data(), kRunMagic, 8) != 0)
    return closed(fail(path + ": not a quack run snapshot (it does not start with \"QUACKRUN\")"));
  auto get = [&](std::size_t at, int count) {
    std::uint64_t v = 0;
    for (int i = 0; i < count; ++i)
      v |= static_cast<std::uint64_t>(bytes[at + static_cast<std::size_t>(i)]) << (8 * i);
    return v;
  };
  if (got >= 12 && get(8, 4) != kRunVersion)
    return closed(fail(path + ": run snapshot version " + std::to_string(get(8, 4)) +
                       " is not this build's (" + std::to_string(kRunVersion) + ")"));
  if (got < kRunHeader)
    return closed(fail(path + ": truncated (" + std::to_string(got) + " bytes)"));
  if (get(kRunChecksumAt, 8) != fnv1a(reinterpret_cast<const char*>(bytes.data()), kRunChecksumAt))
    return closed(fail(path + ": the header's checksum does not match (the file is corrupt)"));
  std::uint8_t buf[65536];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0)
    bytes.insert(bytes.end(), buf, buf + n);
  if (std::ferror(f) != 0) return closed(fail(path + ": read error"));
  std::fclose(f);
  EventTotals t{get(12, 8), get(20, 8), get(28, 8), get(36, 8)};
  Status s = world.restore(std::span<const std::uint8_t>(bytes).subspan(kRunHeader));
  if (!s) return fail(path + ": " + s.message());
  totals = t;
  return {};
}

// The world lets contacts overlap by up to kLinearSlop (5 mm) before pushing them apart, so
// a moving shape only a few millimetres thick sinks by a large part of its size, and one of
// micrometres falls through thin ground (docs/world.md, "Limits"). Such a scene runs as
// asked, with one warning on stderr naming the thinnest.
void warnAboutSmallShapes(const SceneWorld& sw, std::ostream& err) {
  constexpr float kThinnest = 2.0f * kLinearSlop;
  std::size_t thin = 0;
  float smallest = kThinnest;
  std::string where;
  for (std::size_t i = 0; i < sw.bodies.size(); ++i) {
    const BodyId body = sw.bodies[i];
    if (!sw.world.isValid(body) || sw.world.bodyType(body) == BodyType::staticBody) continue;
    for (ShapeId shape : sw.world.shapes(body)) {
      const ShapeGeometry& g = sw.world.geometry(shape);
      if (std::holds_alternative<Segment>(g)) continue;  // no thickness to speak of
      const Aabb box = computeAabb(g, Transform{});
      const float size = std::min(box.upper.x - box.lower.x, box.upper.y - box.lower.y);
      if (size >= kThinnest) continue;
      ++thin;
      if (size < smallest) {
        smallest = size;
        where = i < sw.names.size() ? sw.names[i] : std::to_string(i);
      }
    }
  }
  if (thin == 0) return;
  char size[32];
  std::snprintf(size, sizeof size, "%.3g", static_cast<double>(smallest));
  err << "quack run: warning: " << thin << " moving shape" << (thin == 1 ? " is" : "s are")
      << " thinner than 1 cm (the thinnest, on body \"" << where << "\", is " << size
      << " m); contacts may overlap by 5 mm (kLinearSlop), so such shapes sink or pass "
         "through thin ground (docs/world.md, \"Limits\")\n";
}

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// What a run of either dimension shares once its outputs are checked.
struct RunContext {
  const RunOptions& options;
  std::vector<Output>& outputs;
  Progress& progress;
  std::ostream& out;
  std::ostream& err;

  void phase(const char* name) const {
    if (options.onPhase) options.onPhase(name);
  }
  // The output of `option` ("--html"); it was asked for.
  std::string& text(const char* option) {
    for (Output& o : outputs) {
      if (o.option == option) return o.text;
    }
    QUACK_ASSERT(false);
    return outputs[0].text;
  }
};

// Calls `step(i)` for i = 0 .. count - 1, showing progress and stopping at a signal;
// `step` returns kRunOk, or the status to exit with once it has said why. kRunOk, or the
// status to exit with.
template <class Step>
int simulate(RunContext& run, std::uint64_t count, Step&& step) {
  Progress& progress = run.progress;
  progress.begin("simulating", std::to_string(count) + " steps");
  for (std::uint64_t i = 0; i < count; ++i) {
    if (gSignal != 0) return interruptedStatus();
    if (int status = step(i); status != kRunOk) return status;
    progress.update([&] {
      double elapsed = progress.elapsed();
      double rate = static_cast<double>(i + 1) / elapsed;
      double left = static_cast<double>(count - i - 1) / rate;
      char line[160];
      std::snprintf(line, sizeof line, "step %llu/%llu (%.0f%%), %s, %s left",
                    static_cast<unsigned long long>(i + 1), static_cast<unsigned long long>(count),
                    100.0 * static_cast<double>(i + 1) / static_cast<double>(count),
                    formatRate(rate).c_str(), formatSeconds(left).c_str());
      return std::string(line);
    });
  }
  return kRunOk;
}

// Every output to its temporary file, the timing file last (`timingText(ms)` makes it,
// given how long the others took), then each renamed over its target once all are
// complete. kRunOk, or the status to exit with; `writeMs` says how long it took.
int commitOutputs(RunContext& run, const std::function<std::string(double)>& timingText,
                  double& writeMs) {
  run.phase("write");
  const auto t0 = Clock::now();
  std::size_t total = 0, written = 0;
  for (const Output& o : run.outputs)
    total += o.text.size();
  run.progress.begin("writing", formatBytes(total));
  bool ok = true;
  for (Output& o : run.outputs) {
    if (&o == &run.outputs.back() && !run.options.timing.empty()) o.text = timingText(msSince(t0));
    if (!writeTemp(o, run.progress, written, total, run.err)) {
      ok = false;
      break;
    }
  }
  writeMs = msSince(t0);
  if (ok && gSignal == 0) run.phase("commit");
  if (!ok || gSignal != 0) {
    removeTemps(run.outputs);
    return gSignal != 0 ? interruptedStatus() : kRunFailed;
  }
  for (Output& o : run.outputs) {
    std::error_code ec;
    fs::rename(o.temp, o.target, ec);
    if (ec) {
      run.err << "quack run: cannot move " << o.temp << " to " << o.path << ": " << ec.message()
              << '\n';
      removeTemps(run.outputs);
      return kRunFailed;
    }
    o.temp.clear();
  }
  run.progress.end([&] { return formatBytes(total) + " in " + formatSeconds(writeMs / 1000.0); });
  return kRunOk;
}

// The summary's last lines: how long each phase took and the files written.
void summarizeFiles(RunContext& run, double loadMs, double buildMs, double simulateMs,
                    double renderMs, double writeMs, const std::string& replayNote) {
  const RunOptions& options = run.options;
  std::ostream& out = run.out;
  char line[256];
  std::snprintf(line, sizeof line,
                "time      load %.1f ms, build %.1f ms, simulate %.1f ms, render %.1f ms, "
                "write %.1f ms\n",
                loadMs, buildMs, simulateMs, renderMs, writeMs);
  out << line;
  out << "state     " << options.out << '\n';
  if (!options.events.empty()) out << "event log " << options.events << '\n';
  if (!options.svg.empty()) out << "svg       " << options.svg << '\n';
  if (!options.html.empty()) out << "replay    " << options.html << " (" << replayNote << ")\n";
  if (!options.timing.empty()) out << "timing    " << options.timing << '\n';
}

std::string speedLine(double msPerStep, int threads) {
  char line[160];
  std::snprintf(line, sizeof line, "speed     %.3f ms/step (%s, %d thread%s)\n", msPerStep,
                formatRate(msPerStep > 0 ? 1000.0 / msPerStep : 0.0).c_str(), threads,
                threads == 1 ? "" : "s");
  return line;
}

// The build phase of either dimension: `build()` timed into buildMs with its progress line.
// Fails with an empty message when a signal stopped it (the caller answers as interrupted),
// else with the build's error, already printed.
template <class Build>
auto buildTimed(RunContext& run, std::size_t bodies, double& buildMs, Build&& build)
    -> decltype(build()) {
  run.phase("build");
  const auto t0 = Clock::now();
  run.progress.begin("building the world", std::to_string(bodies) + " bodies");
  auto built = build();
  if (gSignal != 0) return Error{""};
  if (!built) {
    run.err << "quack run: " << built.error().message << '\n';
    return Error{"build failed"};
  }
  run.progress.end([&] { return "done in " + formatSeconds(run.progress.elapsed()); });
  buildMs = msSince(t0);
  return built;
}

// ---- the 2D run ---------------------------------------------------------------------------

// Puts --resume's run snapshot into the world (World or World3) and the totals; false, with
// the message on err, when it cannot.
template <class AnyWorld>
bool restoreRun(const RunOptions& options, AnyWorld& world, EventTotals& totals,
                std::ostream& err) {
  const Status s = readRunSnapshot(options.resume, world, totals);
  if (!s) err << "quack run: --resume " << s.message() << '\n';
  return s.ok();
}

// A resumed world's step against --steps and --snapshot-at (2D and 3D alike); false, with
// the message on err, when the run cannot go on from there.
bool resumedStepFits(const RunOptions& options, std::uint64_t step, std::ostream& err) {
  if (step > options.steps) {
    err << "quack run: --resume " << options.resume << ": the snapshot is at step " << step
        << ", after --steps " << options.steps << '\n';
    return false;
  }
  if (!options.snapshotFile.empty() && options.snapshotAt < step) {
    err << "quack run: --snapshot-at: step " << options.snapshotAt
        << " is before the resumed run's first (" << step << ")\n";
    return false;
  }
  return true;
}

// --threads as a worker count: 0 is the machine's cores, then within 1..kMaxWorkers.
int workersFor(const RunOptions& options) {
  int threads = options.threads;
  if (threads == 0) threads = static_cast<int>(std::thread::hardware_concurrency());
  return std::clamp(threads, 1, kMaxWorkers);
}

int runScene2(RunContext& run, Scene& scene, double loadMs,
              const std::function<bool(std::size_t, std::size_t)>& bodiesProgress) {
  const RunOptions& options = run.options;
  std::ostream& out = run.out;
  std::ostream& err = run.err;
  Progress& progress = run.progress;
  const bool snapshotWanted = !options.snapshotFile.empty();

  // Threads: whatever the file says, the command line decides (the bits do not depend on it).
  const int threads = workersFor(options);
  scene.world.workerCount = threads;

  double buildMs = 0.0;
  Result<SceneWorld> built = buildTimed(run, scene.bodies.size(), buildMs,
                                        [&] { return buildWorld(scene, bodiesProgress); });
  if (!built) return built.error().message.empty() ? interruptedStatus() : kRunFailed;
  SceneWorld& sw = built.value();
  warnAboutSmallShapes(sw, err);
  // The world has its own copy of everything now: free the parsed bodies (about 1 GB for a
  // million generated bodies) before simulating.
  std::vector<SceneBody>().swap(scene.bodies);

  EventTotals totals;
  if (!options.resume.empty()) {
    if (!restoreRun(options, sw.world, totals, err)) return kRunFailed;
    if (!resumedStepFits(options, sw.world.stepCount(), err)) return kRunFailed;
  }
  const std::uint64_t firstStep = sw.world.stepCount();
  const std::uint64_t stepsToRun = options.steps - firstStep;
  // The snapshot, taken when the world reaches its step (before the loop when that is now).
  auto takeSnapshot = [&]() -> bool {
    if (!snapshotWanted || sw.world.stepCount() != options.snapshotAt) return true;
    Result<std::vector<std::uint8_t>> bytes = sw.world.snapshot(SnapshotKind::dynamic);
    if (!bytes) {
      err << "quack run: --snapshot-at: " << bytes.error().message << '\n';
      return false;
    }
    run.text("--snapshot-at") = writeRunSnapshot(totals, bytes.value());
    return true;
  };
  if (!takeSnapshot()) return kRunFailed;

  ReplayOptions replayOptions;
  replayOptions.broadPhaseBoxes = options.htmlBoxes;
  std::optional<ReplayRecorder> replay;
  if (!options.html.empty()) {
    replay.emplace(sw, stepsToRun + 1, replayOptions);
    replay->record(sw);
  }

  run.phase("simulate");
  std::string eventLines;
  auto t0 = Clock::now();
  const int simulated = simulate(run, stepsToRun, [&](std::uint64_t i) {
    if (Status s = sw.world.step(); !s) {
      err << "quack run: step " << firstStep + i + 1 << ": " << s.message() << '\n';
      return kRunFailed;
    }
    const StepEvents& e = sw.world.events();
    totals.begin += e.begin.size();
    totals.end += e.end.size();
    totals.hit += e.hit.size();
    totals.sensor += e.sensorBegin.size();
    if (!options.events.empty()) appendEventLines(eventLines, firstStep + i + 1, e);
    if (replay) replay->record(sw);
    return takeSnapshot() ? kRunOk : kRunFailed;
  });
  if (simulated != kRunOk) return simulated;
  const double simulateMs = msSince(t0);
  progress.end([&] {
    return std::to_string(stepsToRun) + " steps in " + formatSeconds(simulateMs / 1000.0);
  });
  if (gSignal != 0) return interruptedStatus();

  run.phase("render");
  t0 = Clock::now();
  progress.begin("rendering", "the state file");
  run.text("--out") = writeState(captureState(sw, totals));
  if (!options.events.empty()) run.text("--events") = std::move(eventLines);
  if (!options.svg.empty()) {
    if (gSignal != 0) return interruptedStatus();
    progress.update([] { return std::string("the SVG"); });
    run.text("--svg") = renderSvg(sw, options.scene);
  }
  if (!options.html.empty()) {
    if (gSignal != 0) return interruptedStatus();
    progress.update([] { return std::string("the replay"); });
    run.text("--html") = replay->html(options.scene);
  }
  const double renderMs = msSince(t0);
  progress.end([&] { return "done in " + formatSeconds(renderMs / 1000.0); });

  double writeMs = 0.0;
  if (int s = commitOutputs(
          run,
          [&](double ms) {
            return timingJson(stepsToRun, threads, loadMs, buildMs, simulateMs, renderMs, ms);
          },
          writeMs);
      s != kRunOk) {
    return s;
  }

  std::size_t dynamicBodies = 0, movingBodies = 0;
  for (BodyId b : sw.bodies) {
    if (!sw.world.isValid(b)) continue;
    if (sw.world.bodyType(b) == BodyType::dynamicBody) ++dynamicBodies;
    if (sw.world.bodyType(b) != BodyType::staticBody) ++movingBodies;
  }
  const double msPerStep = stepsToRun > 0 ? simulateMs / static_cast<double>(stepsToRun) : 0;
  char line[256];
  out << "scene     " << options.scene << '\n';
  std::snprintf(line, sizeof line, "bodies    %zu (%zu dynamic), %zu shapes\n",
                sw.world.bodyCount(), dynamicBodies, sw.world.shapeCount());
  out << line;
  std::snprintf(line, sizeof line,
                "steps     %llu (%.3f s simulated, dt %.6g s, %d sub-steps, broad phase %s)\n",
                static_cast<unsigned long long>(options.steps), sw.world.time(),
                static_cast<double>(scene.world.timeStep), scene.world.substeps,
                toString(scene.world.broadPhase));
  out << line;
  std::snprintf(line, sizeof line,
                "contacts  %zu touching at the end (%zu pairs with overlapping boxes)\n",
                sw.world.touchingContactCount(), sw.world.contactCount());
  out << line;
  // Static bodies are never awake, so they are not counted.
  std::snprintf(
      line, sizeof line, "awake     %zu of %zu non-static bodies at the end (%zu island%s%s)\n",
      sw.world.awakeBodyCount(), movingBodies, sw.world.islandCount(),
      sw.world.islandCount() == 1 ? "" : "s", scene.world.enableSleep ? "" : ", sleeping off");
  out << line;
  std::snprintf(
      line, sizeof line, "events    begin %llu, end %llu, hit %llu, sensor %llu\n",
      static_cast<unsigned long long>(totals.begin), static_cast<unsigned long long>(totals.end),
      static_cast<unsigned long long>(totals.hit), static_cast<unsigned long long>(totals.sensor));
  out << line;
  out << speedLine(msPerStep, threads);
  std::string replayNote;
  if (replay) {
    replayNote = std::to_string(replay->frameCount()) + " frames";
    if (replay->shapesDrawn() < replay->shapesTotal())
      replayNote += ", " + std::to_string(replay->shapesDrawn()) + " of " +
                    std::to_string(replay->shapesTotal()) + " shapes drawn";
    replayNote += "; open it in a browser";
  }
  summarizeFiles(run, loadMs, buildMs, simulateMs, renderMs, writeMs, replayNote);
  return kRunOk;
}

// ---- the 3D run ---------------------------------------------------------------------------

// The options World3 cannot honour yet, refused before anything is built (docs/world3.md,
// "Not yet").
bool checkOptions3(const RunOptions& options, std::ostream& err) {
  auto refuse = [&](const char* option, const char* why) {
    err << "quack run: " << option << ": " << why << " (" << options.scene << " is a 3D scene)\n";
    return false;
  };
  if (!options.svg.empty())
    return refuse("--svg",
                  "a 3D scene has no SVG picture; its picture is the WebGL replay (--html)");
  if (options.htmlBoxes)
    return refuse("--html-boxes", "the 3D replay does not draw the broad phase's boxes");
  return true;
}

int runScene3(RunContext& run, Scene3& scene, double loadMs,
              const std::function<bool(std::size_t, std::size_t)>& bodiesProgress) {
  const RunOptions& options = run.options;
  std::ostream& out = run.out;
  std::ostream& err = run.err;
  Progress& progress = run.progress;
  if (!checkOptions3(options, err)) return kRunFailed;
  // Threads: whatever the file says, the command line decides (the bits do not depend on it).
  const int threads = workersFor(options);
  scene.world.workerCount = threads;

  double buildMs = 0.0;
  Result<SceneWorld3> built = buildTimed(run, scene.bodies.size(), buildMs,
                                         [&] { return buildWorld3(scene, bodiesProgress); });
  if (!built) return built.error().message.empty() ? interruptedStatus() : kRunFailed;
  SceneWorld3& sw = built.value();
  const bool snapshotWanted = !options.snapshotFile.empty();

  EventTotals totals;
  if (!options.resume.empty()) {
    // A 3D snapshot holds the whole world, so it would put any world in place of this
    // scene's: one of another scene (other bodies or shapes) is refused, or the state file
    // would give this scene's names to another's bodies.
    const std::size_t bodies = sw.world.bodyCount(), shapes = sw.world.shapeCount();
    if (!restoreRun(options, sw.world, totals, err)) return kRunFailed;
    const bool same = sw.world.bodyCount() == bodies && sw.world.shapeCount() == shapes &&
                      std::all_of(sw.bodies.begin(), sw.bodies.end(),
                                  [&](BodyId3 b) { return sw.world.isValid(b); });
    if (!same) {
      err << "quack run: --resume " << options.resume << ": the snapshot is of another scene ("
          << sw.world.bodyCount() << " bodies, " << sw.world.shapeCount() << " shapes; "
          << options.scene << " has " << bodies << " and " << shapes << ")\n";
      return kRunFailed;
    }
    if (!resumedStepFits(options, sw.world.stepCount(), err)) return kRunFailed;
  }
  const std::uint64_t firstStep = sw.world.stepCount();
  const std::uint64_t stepsToRun = options.steps - firstStep;
  // The snapshot, taken when the world reaches its step (before the loop when that is now).
  auto takeSnapshot = [&] {
    if (snapshotWanted && sw.world.stepCount() == options.snapshotAt)
      run.text("--snapshot-at") = writeRunSnapshot(totals, sw.world.snapshot());
  };
  takeSnapshot();

  // The replay draws the scene's shapes (World3 does not hand them back), so the parsed
  // scene is kept.
  std::optional<ReplayRecorder3> replay;
  if (!options.html.empty()) {
    replay.emplace(scene, sw, stepsToRun + 1);
    replay->record(sw);
  }

  run.phase("simulate");
  std::string eventLines;
  auto t0 = Clock::now();
  const int simulated = simulate(run, stepsToRun, [&](std::uint64_t i) {
    if (Status s = sw.world.step(); !s) {
      err << "quack run: step " << firstStep + i + 1 << ": " << s.message() << '\n';
      return kRunFailed;
    }
    const StepEvents3& e = sw.world.events();
    totals.begin += e.begin.size();
    totals.end += e.end.size();
    if (!options.events.empty()) appendEventLines3(eventLines, firstStep + i + 1, e);
    if (replay) replay->record(sw);
    takeSnapshot();
    return kRunOk;
  });
  if (simulated != kRunOk) return simulated;
  const double simulateMs = msSince(t0);
  progress.end([&] {
    return std::to_string(stepsToRun) + " steps in " + formatSeconds(simulateMs / 1000.0);
  });
  if (gSignal != 0) return interruptedStatus();

  run.phase("render");
  t0 = Clock::now();
  progress.begin("rendering", "the state file");
  const StateFile3 state = captureState3(sw, totals);
  run.text("--out") = writeState3(state);
  if (!options.events.empty()) run.text("--events") = std::move(eventLines);
  if (!options.html.empty()) {
    if (gSignal != 0) return interruptedStatus();
    progress.update([] { return std::string("the replay"); });
    run.text("--html") = replay->html(options.scene);
  }
  const double renderMs = msSince(t0);
  progress.end([&] { return "done in " + formatSeconds(renderMs / 1000.0); });

  double writeMs = 0.0;
  if (int s = commitOutputs(
          run,
          [&](double ms) {
            return timingJson(stepsToRun, threads, loadMs, buildMs, simulateMs, renderMs, ms);
          },
          writeMs);
      s != kRunOk) {
    return s;
  }

  std::size_t dynamicBodies = 0, movingBodies = 0;
  for (BodyId3 b : sw.bodies) {
    if (!sw.world.isValid(b)) continue;
    if (sw.world.bodyType(b) == BodyType::dynamicBody) ++dynamicBodies;
    if (sw.world.bodyType(b) != BodyType::staticBody) ++movingBodies;
  }
  const double msPerStep = stepsToRun > 0 ? simulateMs / static_cast<double>(stepsToRun) : 0.0;
  char line[256];
  out << "scene     " << options.scene << " (3D)\n";
  std::snprintf(line, sizeof line, "bodies    %zu (%zu dynamic), %zu shapes\n",
                sw.world.bodyCount(), dynamicBodies, sw.world.shapeCount());
  out << line;
  std::snprintf(line, sizeof line, "steps     %llu (%.3f s simulated, dt %.6g s, %d sub-steps)\n",
                static_cast<unsigned long long>(options.steps), state.time,
                static_cast<double>(scene.world.timeStep), scene.world.substeps);
  out << line;
  std::snprintf(line, sizeof line,
                "contacts  %zu touching at the end (%zu pairs with overlapping boxes)\n",
                sw.world.touchingContactCount(), sw.world.contactCount());
  out << line;
  std::snprintf(line, sizeof line, "awake     %zu of %zu non-static bodies at the end%s\n",
                sw.world.awakeBodyCount(), movingBodies,
                scene.world.enableSleep ? "" : " (sleeping off)");
  out << line;
  std::snprintf(line, sizeof line, "events    begin %llu, end %llu\n",
                static_cast<unsigned long long>(totals.begin),
                static_cast<unsigned long long>(totals.end));
  out << line;
  out << speedLine(msPerStep, threads);
  std::string replayNote;
  if (replay) {
    replayNote = std::to_string(replay->frameCount()) + " frames";
    if (replay->shapesDrawn() < replay->shapesTotal())
      replayNote += ", " + std::to_string(replay->shapesDrawn()) + " of " +
                    std::to_string(replay->shapesTotal()) + " shapes drawn";
    replayNote += "; WebGL, open it in a browser";
  }
  summarizeFiles(run, loadMs, buildMs, simulateMs, renderMs, writeMs, replayNote);
  return kRunOk;
}

}  // namespace

int runScene(const RunOptions& options, std::ostream& out, std::ostream& err) {
  SignalGuard signals;
  std::vector<Output> outputs;
  outputs.push_back({"--out", options.out, {}, {}, {}});
  if (!options.events.empty()) outputs.push_back({"--events", options.events, {}, {}, {}});
  if (!options.svg.empty()) outputs.push_back({"--svg", options.svg, {}, {}, {}});
  if (!options.html.empty()) outputs.push_back({"--html", options.html, {}, {}, {}});
  if (!options.timing.empty()) outputs.push_back({"--timing", options.timing, {}, {}, {}});
  const bool snapshotWanted = !options.snapshotFile.empty();
  if (snapshotWanted) outputs.push_back({"--snapshot-at", options.snapshotFile, {}, {}, {}});
  if (!checkOutputs(outputs, options.scene, err)) return kRunFailed;
  if (snapshotWanted && options.snapshotAt > options.steps) {
    err << "quack run: --snapshot-at: step " << options.snapshotAt << " is after the last step ("
        << options.steps << ")\n";
    return kRunFailed;
  }

  Progress progress(err, !options.quiet, options.progressAfter);
  RunContext run{options, outputs, progress, out, err};
  // A long loop asks this whether to go on: it shows progress and stops at a signal.
  const std::function<bool(std::size_t, std::size_t)> bodiesProgress = [&](std::size_t done,
                                                                           std::size_t total) {
    progress.update([&] {
      return std::to_string(done) + (total ? " of " + std::to_string(total) : "") + " bodies";
    });
    return gSignal == 0;
  };

  run.phase("load");
  const auto t0 = Clock::now();
  progress.begin("loading", options.scene);
  Result<AnyScene> scene = loadAnyScene(options.scene, bodiesProgress);
  if (gSignal != 0) return interruptedStatus();
  if (!scene) {
    err << "quack run: " << scene.error().message << '\n';
    return kRunFailed;
  }
  Scene3* scene3 = std::get_if<Scene3>(&*scene);
  progress.end([&] {
    return std::to_string(scene3 ? scene3->bodies.size() : std::get<Scene>(*scene).bodies.size()) +
           " bodies";
  });
  const double loadMs = msSince(t0);
  if (scene3 != nullptr) return runScene3(run, *scene3, loadMs, bodiesProgress);
  return runScene2(run, std::get<Scene>(*scene), loadMs, bodiesProgress);
}

}  // namespace quack::app
