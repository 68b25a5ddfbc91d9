// Result<T>: the value of a fallible operation, or a message a user can act on.
//
// Used at every boundary that can fail for reasons outside the program (files, plugins,
// devices, user input). Programmer errors use assert instead.
#pragma once

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace qp {

struct Error {
    std::string message;  // complete sentence naming the file, line or field at fault
};

template <class T>
class [[nodiscard]] Result {
public:
    Result(T value) : state_(std::move(value)) {}
    Result(Error error) : state_(std::move(error)) {}

    bool ok() const { return state_.index() == 0; }
    explicit operator bool() const { return ok(); }

    T& value() & { assert(ok()); return std::get<0>(state_); }
    const T& value() const& { assert(ok()); return std::get<0>(state_); }
    T&& value() && { assert(ok()); return std::get<0>(std::move(state_)); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }

    const Error& error() const { assert(!ok()); return std::get<1>(state_); }

private:
    std::variant<T, Error> state_;
};

// Result of an operation that yields nothing on success.
struct Done {};
using Status = Result<Done>;

inline Status success() { return Done{}; }

}  // namespace qp
