// Exceptions thrown by slamkit. Every error that comes from user input says where:
// InputError carries the file, the 1-based line and the field that is wrong, and its
// what() reads "FILE:LINE: field 'F': message" so a CLI can print it as is.
#pragma once

#include <stdexcept>
#include <string>

namespace slamkit {

/// Base of all slamkit exceptions.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Malformed, inconsistent or unusable input (files, graphs, options).
class InputError : public Error {
 public:
  InputError(std::string file, int line, std::string field, const std::string& message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }  ///< 0 when the error concerns the whole input
  const std::string& field() const { return field_; }

 private:
  std::string file_;
  int line_;
  std::string field_;
};

/// A numerical failure the caller can act on (e.g. a factorization that is not positive definite).
class NumericalError : public Error {
 public:
  using Error::Error;
};

}  // namespace slamkit
