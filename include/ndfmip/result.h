// Error reporting across the library boundary: no exceptions leave ndfmip, bad data from
// outside (files, parameters) comes back as an Error with a one-line message.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <variant>

namespace ndfmip {

struct Error {
    std::string message; // one line, names the file or parameter and the problem
};

// A value or an Error. Check ok() before value().
template <class T> class Result {
  public:
    Result(T value) : data_(std::move(value)) {}
    Result(Error error) : data_(std::move(error)) {}

    bool ok() const { return std::holds_alternative<T>(data_); }
    explicit operator bool() const { return ok(); }
    T& value() { return std::get<T>(data_); }
    const T& value() const { return std::get<T>(data_); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    const Error& error() const { return std::get<Error>(data_); }

  private:
    std::variant<T, Error> data_;
};

// Success or an Error, for operations with no value.
struct Status {
    std::string error; // empty on success
    bool ok() const { return error.empty(); }
    explicit operator bool() const { return ok(); }
    static Status success() { return {}; }
    static Status failure(std::string message) { return {std::move(message)}; }
};

// Text from a file or the command line as an error message quotes it: in single quotes, control
// characters as '?', cut after `maxChars` bytes (at a UTF-8 boundary) with "…", so a 10 MB key
// cannot become a 10 MB error line.
std::string quote(std::string_view text, size_t maxChars = 80);

// The same without the quotes (file paths read from a file).
std::string shortened(std::string_view text, size_t maxChars = 80);

} // namespace ndfmip
