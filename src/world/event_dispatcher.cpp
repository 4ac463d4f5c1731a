#include "event_dispatcher.hpp"

#include "body_store.hpp"
#include "contact_set.hpp"

namespace quack::detail {
namespace {

bool matches(std::uint64_t categories, std::uint64_t wanted) {
  return (categories & wanted) != 0;
}

}  // namespace

void EventDispatcher::beginStep() {
  events.begin.clear();
  events.end.clear();
  endCategories_.clear();
  events.sensorEnd.clear();
  sensorEndCategories_.clear();
  for (const PendingEnd& e : endsSinceStep_) {
    if (e.sensor) {
      events.sensorEnd.push_back({e.shapeA, e.shapeB});
      sensorEndCategories_.push_back({e.categoryA, e.categoryB});
    } else {
      events.end.push_back({e.shapeA, e.shapeB});
      endCategories_.push_back({e.categoryA, e.categoryB});
    }
  }
  endsSinceStep_.clear();
  events.hit.clear();
  events.sensorBegin.clear();
  events.toi.clear();
  events.outOfBounds.clear();
  events.toiCapped.clear();
  events.jointEnd.clear();
}

void EventDispatcher::contactEnded(const BodyStore& store, const Contact& c, bool inStep) {
  const ShapeId a = store.shapeId(c.shapeA), b = store.shapeId(c.shapeB);
  const std::array<std::uint64_t, 2> categories{store.shapes[c.shapeA].def.filter.category,
                                                store.shapes[c.shapeB].def.filter.category};
  if (!inStep) {
    // Destroyed between steps: reported (events and callbacks) with the next step.
    endsSinceStep_.push_back({a, b, categories[0], categories[1], c.sensor});
  } else if (c.sensor) {
    events.sensorEnd.push_back({a, b});
    sensorEndCategories_.push_back(categories);
  } else {
    events.end.push_back({a, b});
    endCategories_.push_back(categories);
  }
}

void EventDispatcher::add(Kind kind, std::uint64_t a, std::uint64_t b,
                          World::ContactCallback contact, World::HitCallback hit, bool fromCallback,
                          World::ImpactCallback impact) {
  (fromCallback ? pending_ : callbacks_)
      .push_back({kind, a, b, std::move(contact), std::move(hit), std::move(impact)});
}

void EventDispatcher::addJointEnd(World::JointEndCallback f, bool fromCallback) {
  Callback cb{Kind::jointEnd, 0, 0, {}, {}, {}, std::move(f)};
  (fromCallback ? pending_ : callbacks_).push_back(std::move(cb));
}

void EventDispatcher::dispatch(World& world, const BodyStore& store) {
  if (callbacks_.empty()) return;
  // Every event in the lists gets its callbacks, so the two always agree. End events may
  // name shapes destroyed since (stale handles); their categories were kept when they
  // ended. The other events' shapes are valid (destruction asked for inside a callback
  // waits until the callbacks are done).
  auto category = [&](ShapeId s) { return store.shapes[s.index].def.filter.category; };
  auto runPairs = [&](Kind kind, const auto& list,
                      const std::vector<std::array<std::uint64_t, 2>>* kept, bool ordered) {
    for (const Callback& cb : callbacks_) {
      if (cb.kind != kind) continue;
      for (std::size_t i = 0; i < list.size(); ++i) {
        const auto& e = list[i];
        ShapeId a{}, b{};
        if constexpr (requires { e.sensor; }) {
          a = e.sensor;
          b = e.visitor;
        } else {
          a = e.shapeA;
          b = e.shapeB;
        }
        const std::uint64_t catA = kept ? (*kept)[i][0] : category(a);
        const std::uint64_t catB = kept ? (*kept)[i][1] : category(b);
        if (matches(catA, cb.categoriesA) && matches(catB, cb.categoriesB)) {
          cb.contact(world, a, b);
        } else if (!ordered && matches(catB, cb.categoriesA) && matches(catA, cb.categoriesB)) {
          cb.contact(world, b, a);
        }
      }
    }
  };
  runPairs(Kind::begin, events.begin, nullptr, false);
  runPairs(Kind::end, events.end, &endCategories_, false);
  runPairs(Kind::sensorBegin, events.sensorBegin, nullptr, true);
  runPairs(Kind::sensorEnd, events.sensorEnd, &sensorEndCategories_, true);
  for (const Callback& cb : callbacks_) {
    if (cb.kind != Kind::hit) continue;
    for (const ContactHitEvent& e : events.hit) {
      if (matches(category(e.shapeA), cb.categoriesA) &&
          matches(category(e.shapeB), cb.categoriesB)) {
        cb.hit(world, e, false);
      } else if (matches(category(e.shapeB), cb.categoriesA) &&
                 matches(category(e.shapeA), cb.categoriesB)) {
        cb.hit(world, e, true);
      }
    }
  }
  for (const Callback& cb : callbacks_) {
    if (cb.kind != Kind::impact) continue;
    for (const ToiEvent& e : events.toi) {
      if (matches(category(e.shapeA), cb.categoriesA) &&
          matches(category(e.shapeB), cb.categoriesB)) {
        cb.impact(world, e, false);
      } else if (matches(category(e.shapeB), cb.categoriesA) &&
                 matches(category(e.shapeA), cb.categoriesB)) {
        cb.impact(world, e, true);
      }
    }
  }
  for (const Callback& cb : callbacks_) {
    if (cb.kind != Kind::jointEnd) continue;
    for (const JointEndEvent& e : events.jointEnd)
      cb.jointEnd(world, e);
  }
  for (Callback& cb : pending_)
    callbacks_.push_back(std::move(cb));
  pending_.clear();
}

}  // namespace quack::detail
