// The project's one error type. Every domain error (TraceError, SceneFileError, ...)
// derives from it, so a program can catch core::Error once at its top and print what().
// Messages read `file: field: problem` ("scene.json: room.shell.max: expected a number,
// got a string"): the reader of a message is the person who edits the file, and the file
// and the field are what they need to find the mistake.
#pragma once

#include <stdexcept>
#include <string>

namespace penumbra::core {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  // `file: field: problem`; an empty field leaves it out (`file: problem`).
  Error(const std::string& file, const std::string& field, const std::string& problem)
      : std::runtime_error(file + ": " + (field.empty() ? "" : field + ": ") + problem) {}
};

}  // namespace penumbra::core
