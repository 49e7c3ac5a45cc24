// Value-or-error for solver entry points: math that can fail on legitimate input returns
// Result<T> with the offending input named, never throws, never yields NaN or Inf.
#pragma once

#include <charconv>
#include <string>
#include <utility>
#include <variant>

namespace lixel {

// Why a solve was refused: `field` is the input's path ("plane", "viewer[2][1]",
// "light.w"), `reason` says what is wrong with it in words a caller can act on.
struct Error {
    std::string field;
    std::string reason;

    std::string Message() const { return field + ": " + reason; }
};

// A number as a refusal quotes it: the shortest text that reads back as the same double
// (1e-300 and 1e+300, where std::to_string writes 0.000000 and 301 digits).
inline std::string ShortestText(double value) {
    char text[32];
    return std::string(text, std::to_chars(text, text + sizeof text, value).ptr);
}

template <class T>
class [[nodiscard]] Result {
public:
    Result(T value) : state_(std::move(value)) {}  // NOLINT(google-explicit-constructor)
    Result(Error error) : state_(std::move(error)) {}  // NOLINT(google-explicit-constructor)

    bool ok() const noexcept { return state_.index() == 0; }
    explicit operator bool() const noexcept { return ok(); }

    // Valid only when ok().
    const T& value() const& { return std::get<0>(state_); }
    T& value() & { return std::get<0>(state_); }
    T&& value() && { return std::get<0>(std::move(state_)); }
    const T* operator->() const { return &std::get<0>(state_); }
    T* operator->() { return &std::get<0>(state_); }
    const T& operator*() const& { return value(); }

    // Valid only when !ok().
    const Error& error() const& { return std::get<1>(state_); }

private:
    std::variant<T, Error> state_;
};

}  // namespace lixel
