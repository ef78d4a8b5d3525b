// The one error type for bad input: it names the file, the element and what is wrong.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace pbs {

// what() reads "FILE: ELEMENT: PROBLEM" (ELEMENT omitted when empty); the CLI prints it after
// "error: " on one line and exits with status 1.
class InputError : public std::runtime_error {
 public:
  InputError(std::string_view file, std::string_view element, std::string_view problem)
      : std::runtime_error(compose(file, element, problem)) {}

 private:
  static std::string compose(std::string_view file, std::string_view element, std::string_view problem) {
    std::string text(file);
    if (!element.empty()) text.append(": ").append(element);
    text.append(": ").append(problem);
    return text;
  }
};

}  // namespace pbs
