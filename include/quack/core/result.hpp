#pragma once
/// `Result<T>`: a value, or an error message that names what was wrong.
///
/// Public functions that can be given bad input (a NaN coordinate, a negative radius, a
/// concave point set passed as convex) return a `Result` rather than asserting, so a
/// caller can reject one bad item and keep everything it already has.
///
/// ```
/// Result<Polygon> p = makePolygon(points, 0.0f);
/// if (!p) std::cerr << p.error().message << '\n';
/// else use(p.value());
/// ```

#include <string>
#include <type_traits>
#include <utility>
#include <variant>

#include "quack/core/assert.hpp"

namespace quack {

/// What went wrong, in words a user can act on ("polygon.points[3] is NaN").
struct Error {
  std::string message;
};

/// Builds an `Error`; reads well at a return site: `return fail("radius is negative");`.
inline Error fail(std::string message) {
  return Error{std::move(message)};
}

template <class T>
class [[nodiscard]] Result {
  static_assert(!std::is_same_v<T, Error>, "Result<Error> is ambiguous");

 public:
  Result(const T& value) : state_(std::in_place_index<0>, value) {}  // NOLINT: implicit by design
  Result(T&& value) : state_(std::in_place_index<0>, std::move(value)) {}    // NOLINT
  Result(Error error) : state_(std::in_place_index<1>, std::move(error)) {}  // NOLINT

  bool ok() const noexcept { return state_.index() == 0; }
  explicit operator bool() const noexcept { return ok(); }

  /// Precondition: `ok()`.
  const T& value() const& {
    QUACK_ASSERT_MSG(ok(), "Result::value() on an error");
    return std::get<0>(state_);
  }
  T& value() & {
    QUACK_ASSERT_MSG(ok(), "Result::value() on an error");
    return std::get<0>(state_);
  }
  T&& value() && {
    QUACK_ASSERT_MSG(ok(), "Result::value() on an error");
    return std::get<0>(std::move(state_));
  }
  const T& operator*() const& { return value(); }
  T& operator*() & { return value(); }
  const T* operator->() const { return &value(); }
  T* operator->() { return &value(); }

  /// Precondition: `!ok()`.
  const Error& error() const& {
    QUACK_ASSERT_MSG(!ok(), "Result::error() on a value");
    return std::get<1>(state_);
  }

  /// The value, or `fallback` when this holds an error.
  T valueOr(T fallback) const& { return ok() ? std::get<0>(state_) : std::move(fallback); }

 private:
  std::variant<T, Error> state_;
};

/// A `Result` for operations that produce nothing but can fail.
class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(Error error) : error_(std::move(error.message)), failed_(true) {}  // NOLINT
  bool ok() const noexcept { return !failed_; }
  explicit operator bool() const noexcept { return ok(); }
  /// Empty when `ok()`.
  const std::string& message() const noexcept { return error_; }

 private:
  std::string error_;
  bool failed_ = false;
};

}  // namespace quack
