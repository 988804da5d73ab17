// The lab protocols' log from Python: a std::ostream whose lines go to Python's sys.stdout (so
// that a notebook, a redirect_stdout or pytest's capture sees them), to a Python callable, or
// nowhere. The protocols write it with the GIL released: each whole line takes the GIL, goes to
// Python and checks for Ctrl-C. An exception there (KeyboardInterrupt, or one the callable
// raises) comes out of the stream's write, so it stops the stage at that line and is raised from
// the stage's call.
#pragma once

#include <pybind11/pybind11.h>

#include <ostream>
#include <streambuf>
#include <string>

namespace dem::python {

class ProgressStream {
 public:
  /// `progress`: None (lines to sys.stdout unless `quiet`), True (sys.stdout), False (nowhere) or a
  /// callable taking one line (str, without its newline). ValueError naming `owner` for another
  /// value, or for quiet=True with progress=True or a callable.
  ProgressStream(const pybind11::object& progress, bool quiet, const std::string& owner);
  ProgressStream(const ProgressStream&) = delete;
  ProgressStream& operator=(const ProgressStream&) = delete;

  /// The stream to hand a protocol. Ready again for the next stage after an exception stopped one.
  std::ostream& stream();
  /// Sends a last line without its newline, if one is pending (after a stage; with the GIL).
  void finish();

 private:
  class Lines : public std::streambuf {
   public:
    explicit Lines(pybind11::object sink) : sink_(std::move(sink)) {}
    void send(bool partial);

   protected:
    int_type overflow(int_type c) override;
    std::streamsize xsputn(const char* s, std::streamsize n) override;
    int sync() override;

   private:
    pybind11::object sink_;  // a callable, or None for sys.stdout
    std::string pending_;
  };

  bool enabled_;
  Lines lines_;
  std::ostream out_;
};

}  // namespace dem::python
