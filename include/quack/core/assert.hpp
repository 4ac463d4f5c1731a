#pragma once
/// Internal-invariant checks for Quack.
///
/// `QUACK_ASSERT(cond)` checks an invariant that holds whatever the caller passes in; bad
/// input at the public boundary is reported through `Result` instead. Asserts are compiled
/// in when `QUACK_ENABLE_ASSERTS` is defined (the debug and sanitizer presets and CI do),
/// and compile to nothing otherwise. A failed assert calls the installed handler; the
/// default one prints the expression and location to stderr and aborts.

namespace quack {

/// Called on a failed assert. `expression` is the source text of the condition, `message`
/// is an optional explanation (may be null). A handler may throw or longjmp (tests do);
/// if it returns, execution continues past the assert.
using AssertHandler = void (*)(const char* expression, const char* message, const char* file,
                               int line);

/// Installs `handler` (null restores the default) and returns the previous handler.
/// Not thread-safe with respect to concurrent asserts; install it at start-up.
AssertHandler setAssertHandler(AssertHandler handler) noexcept;

/// Calls the installed handler. Used by the macros; call it directly only to report an
/// invariant failure from code that cannot use the macro.
void reportAssertFailure(const char* expression, const char* message, const char* file, int line);

}  // namespace quack

#if defined(QUACK_ENABLE_ASSERTS)
#define QUACK_ASSERT(cond)                                                         \
  do {                                                                             \
    if (!(cond)) ::quack::reportAssertFailure(#cond, nullptr, __FILE__, __LINE__); \
  } while (false)
#define QUACK_ASSERT_MSG(cond, msg)                                              \
  do {                                                                           \
    if (!(cond)) ::quack::reportAssertFailure(#cond, (msg), __FILE__, __LINE__); \
  } while (false)
#else
#define QUACK_ASSERT(cond) \
  do {                     \
  } while (false)
#define QUACK_ASSERT_MSG(cond, msg) \
  do {                              \
  } while (false)
#endif
