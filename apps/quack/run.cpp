#include "run.hpp"

#include <unistd.h>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <ostream>

#include "quack/io/render.hpp"
#include "quack/io/scene.hpp"
#include "quack/io/state.hpp"

namespace quack::app {
namespace {

using Clock = std::chrono::steady_clock;

// Outputs are written to a temporary file beside the target and renamed at the end, so a
// failed run never leaves a half-written file or destroys the previous one.
struct Output {
  std::string path;
  std::string temp;
};

bool prepare(Output& o, std::ostream& err) {
  o.temp = o.path + ".part";
  std::ofstream probe(o.temp, std::ios::binary | std::ios::trunc);
  if (!probe) {
    err << "quack run: cannot write " << o.path << '\n';
    return false;
  }
  return true;
}

bool finish(const Output& o, const std::string& text, std::ostream& err) {
  {
    std::ofstream f(o.temp, std::ios::binary | std::ios::trunc);
    f << text;
    if (!f) {
      err << "quack run: writing " << o.path << " failed\n";
      return false;
    }
  }
  std::error_code ec;
  std::filesystem::rename(o.temp, o.path, ec);
  if (ec) {
    err << "quack run: cannot move " << o.temp << " to " << o.path << ": " << ec.message() << '\n';
    return false;
  }
  return true;
}

std::string formatSeconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, s < 60 ? "%.1f s" : "%.0f s", s);
  return buf;
}

}  // namespace

int runScene(const RunOptions& options, std::ostream& out, std::ostream& err) {
  Result<Scene> scene = loadScene(options.scene);
  if (!scene) {
    err << "quack run: " << scene.error().message << '\n';
    return 2;
  }
  Result<SceneWorld> built = buildWorld(scene.value());
  if (!built) {
    err << "quack run: " << built.error().message << '\n';
    return 2;
  }
  SceneWorld& sw = built.value();
  std::vector<Output> outputs;
  outputs.push_back({options.out, ""});
  if (!options.svg.empty()) outputs.push_back({options.svg, ""});
  if (!options.html.empty()) outputs.push_back({options.html, ""});
  for (Output& o : outputs) {
    if (!prepare(o, err)) {
      for (const Output& p : outputs)
        std::remove(p.temp.c_str());
      return 2;
    }
  }

  ReplayOptions replayOptions;
  replayOptions.broadPhaseBoxes = options.htmlBoxes;
  std::optional<ReplayRecorder> replay;
  if (!options.html.empty()) {
    replay.emplace(sw, options.steps + 1, replayOptions);
    replay->record(sw);
  }

  EventTotals totals;
  const bool showProgress = !options.quiet;
  const bool tty = isatty(fileno(stderr)) != 0;
  auto start = Clock::now();
  auto lastReport = start;
  double stepMs = 0.0;
  for (std::uint64_t i = 0; i < options.steps; ++i) {
    auto t0 = Clock::now();
    Status s = sw.world.step();
    stepMs += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (!s) {
      err << "quack run: step " << i << ": " << s.message() << '\n';
      return 2;
    }
    const StepEvents& e = sw.world.events();
    totals.begin += e.begin.size();
    totals.end += e.end.size();
    totals.hit += e.hit.size();
    totals.sensor += e.sensorBegin.size();
    if (replay) replay->record(sw);
    auto now = Clock::now();
    // Progress about once a second, only for runs that take that long.
    if (showProgress && now - lastReport > std::chrono::seconds(1)) {
      lastReport = now;
      double elapsed = std::chrono::duration<double>(now - start).count();
      double rate = static_cast<double>(i + 1) / elapsed;
      double left = static_cast<double>(options.steps - i - 1) / rate;
      char line[160];
      std::snprintf(line, sizeof line, "quack run: step %llu/%llu (%.0f%%), %.0f steps/s, %s left",
                    static_cast<unsigned long long>(i + 1),
                    static_cast<unsigned long long>(options.steps),
                    100.0 * static_cast<double>(i + 1) / static_cast<double>(options.steps), rate,
                    formatSeconds(left).c_str());
      err << line << (tty ? "\r" : "\n") << std::flush;
    }
  }
  double totalMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  if (showProgress && tty && lastReport != start) err << '\n';
  RunTiming timing{options.steps > 0 ? stepMs / static_cast<double>(options.steps) : 0.0, totalMs};

  StateFile state = captureState(sw, totals, timing);
  bool ok = finish(outputs[0], writeState(state), err);
  std::size_t next = 1;
  if (!options.svg.empty()) ok = finish(outputs[next++], renderSvg(sw, options.scene), err) && ok;
  if (!options.html.empty()) ok = finish(outputs[next++], replay->html(options.scene), err) && ok;
  if (!ok) return 2;

  std::size_t dynamicBodies = 0;
  for (BodyId b : sw.bodies) {
    if (sw.world.isValid(b) && sw.world.bodyType(b) == BodyType::dynamicBody) ++dynamicBodies;
  }
  char line[256];
  out << "scene     " << options.scene << '\n';
  std::snprintf(line, sizeof line, "bodies    %zu (%zu dynamic), %zu shapes\n",
                sw.world.bodyCount(), dynamicBodies, sw.world.shapeCount());
  out << line;
  std::snprintf(line, sizeof line,
                "steps     %llu (%.3f s simulated, dt %.6g s, %d sub-steps, broad phase %s)\n",
                static_cast<unsigned long long>(options.steps), sw.world.time(),
                static_cast<double>(scene->world.timeStep), scene->world.substeps,
                std::string(nameOf(scene->world.broadPhase)).c_str());
  out << line;
  std::snprintf(line, sizeof line,
                "contacts  %zu touching at the end (%zu pairs with overlapping boxes)\n",
                sw.world.touchingContactCount(), sw.world.contactCount());
  out << line;
  std::snprintf(
      line, sizeof line, "events    begin %llu, end %llu, hit %llu, sensor %llu\n",
      static_cast<unsigned long long>(totals.begin), static_cast<unsigned long long>(totals.end),
      static_cast<unsigned long long>(totals.hit), static_cast<unsigned long long>(totals.sensor));
  out << line;
  std::snprintf(line, sizeof line, "speed     %.3f ms/step (%.0f steps/s), %.1f ms in all\n",
                timing.msPerStep, timing.msPerStep > 0 ? 1000.0 / timing.msPerStep : 0.0, totalMs);
  out << line;
  out << "state     " << options.out << '\n';
  if (!options.svg.empty()) out << "svg       " << options.svg << '\n';
  if (!options.html.empty()) {
    out << "replay    " << options.html << " (" << replay->frameCount()
        << " frames; open it in a browser)\n";
  }
  return 0;
}

}  // namespace quack::app
