// Rollback with snapshots (docs/determinism.md, "Snapshots"), as a networked game does it.
//
// Two players push crates about. This machine simulates ahead with the inputs it has: its
// own, and for the remote player a guess (the last input heard of). A dynamic snapshot is
// kept for every step. When the remote player's real input for an earlier step arrives and
// differs from the guess, the game restores that step's snapshot and simulates again up to
// now with the corrected inputs. The result must be bit-identical to a world that had the
// right inputs all along; this program checks that and exits 1 if not (it runs as a test).

#include <array>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "quack/quack.hpp"

using namespace quack;

namespace {

// One player's input for one step: push left (-1), right (+1) or not (0), and jump.
struct Input {
  int push = 0;
  bool jump = false;
};

struct Game {
  World world;
  std::array<BodyId, 2> players;
};

Game makeGame() {
  Game g{World::create({}).value(), {}};
  BodyId ground = g.world.createBody({.type = BodyType::staticBody}).value();
  (void)g.world.createShape(ground, {}, makeBox(20.0f, 0.5f, {0.0f, -0.5f}, 0.0f).value());
  for (int i = 0; i < 6; ++i) {
    BodyId crate = g.world.createBody({.position = {-2.5f + static_cast<float>(i), 0.4f}}).value();
    (void)g.world.createShape(crate, {.density = 0.5f}, makeBox(0.4f, 0.4f).value());
  }
  for (int p = 0; p < 2; ++p) {
    g.players[static_cast<std::size_t>(p)] =
        g.world.createBody({.position = {p == 0 ? -6.0f : 6.0f, 0.5f}}).value();
    (void)g.world.createShape(g.players[static_cast<std::size_t>(p)], {.friction = 0.8f},
                              makeCapsule({0.0f, -0.2f}, {0.0f, 0.2f}, 0.3f).value());
  }
  return g;
}

// The game's step: each player's input becomes a force and maybe a jump, then the world
// steps. Everything that reaches the world goes through here, so replaying inputs replays
// the game.
void stepGame(Game& g, const std::array<Input, 2>& inputs) {
  for (std::size_t p = 0; p < 2; ++p) {
    const BodyId b = g.players[p];
    const Vec2 at = g.world.worldCenterOfMass(b);
    (void)g.world.applyForce(b, {40.0f * static_cast<float>(inputs[p].push), 0.0f}, at);
    if (inputs[p].jump) (void)g.world.applyLinearImpulse(b, {0.0f, 6.0f}, at);
  }
  (void)g.world.step();
}

// The players' real inputs, step by step: the local one walks right and jumps at 12; the
// remote one walks left and, at step 20, jumps and turns round, which this machine learns
// only at step 34 (a latency of 14 steps).
std::array<Input, 2> realInputs(int step) {
  Input local{step < 40 ? 1 : 0, step == 12};
  Input remote{step < 20 ? -1 : 1, step == 20};
  return {local, remote};
}

}  // namespace

int main() {
  constexpr int kSteps = 60;
  constexpr int kCorrectionStep = 20;  // the step whose remote input was guessed wrong
  constexpr int kArrivesAt = 34;       // when the real input arrives

  // The reference: a world that had every real input from the start.
  Game reference = makeGame();
  std::vector<std::uint64_t> referenceHash;  // after each step
  for (int step = 0; step < kSteps; ++step) {
    stepGame(reference, realInputs(step));
    referenceHash.push_back(reference.world.stateHash());
  }

  // This machine: predicts the remote input (the last one heard of) and keeps a dynamic
  // snapshot of the state before every step.
  Game game = makeGame();
  std::vector<std::array<Input, 2>> used;            // inputs used for each step so far
  std::vector<std::vector<std::uint8_t>> snapshots;  // state before each step
  Input lastHeard;
  std::size_t snapshotBytes = 0;
  for (int step = 0; step < kSteps; ++step) {
    if (step == kArrivesAt) {
      // The remote player's real inputs from kCorrectionStep on arrive: roll back to the
      // first wrong one, then simulate again up to now with what is known.
      std::printf("step %d: the remote input of step %d arrives; rolling back %d steps\n", step,
                  kCorrectionStep, step - kCorrectionStep);
      // The guess was wrong, so the prediction went astray (else this shows nothing).
      if (game.world.stateHash() == referenceHash[static_cast<std::size_t>(step - 1)]) {
        std::printf("the prediction matched the reference: nothing to correct\n");
        return 1;
      }
      Status restored = game.world.restore(snapshots[kCorrectionStep]);
      if (!restored) {
        std::printf("restore failed: %s\n", restored.message().c_str());
        return 1;
      }
      for (int again = kCorrectionStep; again < step; ++again) {
        used[static_cast<std::size_t>(again)][1] = realInputs(again)[1];
        snapshots[static_cast<std::size_t>(again)] =
            game.world.snapshot(SnapshotKind::dynamic).value();
        stepGame(game, used[static_cast<std::size_t>(again)]);
      }
      lastHeard = realInputs(step - 1)[1];
      if (game.world.stateHash() != referenceHash[static_cast<std::size_t>(step - 1)]) {
        std::printf("MISMATCH right after re-simulating to step %d\n", step);
        return 1;
      }
    }
    // Inputs from the remote player are heard up to kCorrectionStep - 1 on time, then not
    // until kArrivesAt: until then it is predicted to keep doing what it did.
    if (step < kCorrectionStep || step >= kArrivesAt) lastHeard = realInputs(step)[1];
    const std::array<Input, 2> inputs{realInputs(step)[0], lastHeard};
    snapshots.push_back(game.world.snapshot(SnapshotKind::dynamic).value());
    snapshotBytes += snapshots.back().size();
    used.push_back(inputs);
    stepGame(game, inputs);
  }

  const std::uint64_t got = game.world.stateHash(), want = reference.world.stateHash();
  std::printf("%d steps, %zu bytes of snapshots (%zu per step)\n", kSteps, snapshotBytes,
              snapshotBytes / kSteps);
  std::printf("remote player at x = %.4f (reference %.4f)\n",
              static_cast<double>(game.world.position(game.players[1]).x),
              static_cast<double>(reference.world.position(reference.players[1]).x));
  if (got != want) {
    std::printf("MISMATCH: state hash %016llx, reference %016llx\n",
                static_cast<unsigned long long>(got), static_cast<unsigned long long>(want));
    return 1;
  }
  std::printf("re-simulated state matches the reference bit for bit (hash %016llx)\n",
              static_cast<unsigned long long>(got));
  return 0;
}
