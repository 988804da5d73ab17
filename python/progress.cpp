// ProgressStream (progress.hpp): the protocols' log lines to Python.
#include "progress.hpp"

#include <cstring>

#include <dem/core/errors.hpp>

namespace py = pybind11;

namespace dem::python {

namespace {

// What a progress argument asks for: whether lines go anywhere, and the callable they go to
// (None: sys.stdout).
bool wants_lines(const py::object& progress, bool quiet, const std::string& owner) {
  const std::string argument = owner + " progress";
  if (progress.is_none()) return !quiet;
  const bool callable = !py::isinstance<py::bool_>(progress) && PyCallable_Check(progress.ptr());
  if (!callable && !py::isinstance<py::bool_>(progress))
    throw InputError(argument + " = " + py::repr(progress).cast<std::string>() +
                     ": must be True (lines to sys.stdout), False (none), None (sys.stdout unless quiet) or a "
                     "callable taking each line");
  const bool on = callable || progress.cast<bool>();
  if (on && quiet)
    throw InputError(
        argument + " = " + py::repr(progress).cast<std::string>() +
        " with quiet = True: must be False or None (quiet = True is the older spelling of progress = False)");
  return on;
}

py::object sink_of(const py::object& progress) {
  return progress.is_none() || py::isinstance<py::bool_>(progress) ? py::none() : progress;
}

}  // namespace

ProgressStream::ProgressStream(const py::object& progress, bool quiet, const std::string& owner)
    : enabled_(wants_lines(progress, quiet, owner)), lines_(sink_of(progress)), out_(enabled_ ? &lines_ : nullptr) {
  // An exception the sink throws comes out of the protocol's write (the stream sets badbit and
  // rethrows it), instead of being swallowed by the stream.
  if (enabled_) out_.exceptions(std::ios::badbit);
}

std::ostream& ProgressStream::stream() {
  if (enabled_) out_.clear();
  return out_;
}

void ProgressStream::finish() {
  if (enabled_) lines_.send(true);
}

ProgressStream::Lines::int_type ProgressStream::Lines::overflow(int_type c) {
  if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
  pending_.push_back(traits_type::to_char_type(c));
  if (traits_type::to_char_type(c) == '\n') send(false);
  return c;
}

std::streamsize ProgressStream::Lines::xsputn(const char* s, std::streamsize n) {
  pending_.append(s, static_cast<std::size_t>(n));
  if (std::memchr(s, '\n', static_cast<std::size_t>(n)) != nullptr) send(false);
  return n;
}

int ProgressStream::Lines::sync() {
  send(false);
  return 0;
}

// The whole lines pending (and with `partial` the rest too) go to Python, with the GIL.
void ProgressStream::Lines::send(bool partial) {
  const std::size_t end = partial ? pending_.size() : pending_.rfind('\n') + 1;  // npos + 1 == 0
  if (end == 0) return;
  const std::string text = pending_.substr(0, end);
  pending_.erase(0, end);
  py::gil_scoped_acquire gil;
  auto decoded = [](const char* s, std::size_t n) {  // a path in a line may not be UTF-8
    PyObject* str = PyUnicode_DecodeUTF8(s, static_cast<Py_ssize_t>(n), "replace");
    if (str == nullptr) throw py::error_already_set();
    return py::reinterpret_steal<py::str>(str);
  };
  if (sink_.is_none()) {
    const py::object out = py::module_::import("sys").attr("stdout");
    if (!out.is_none()) {  // None: pythonw, or a closed stdout
      out.attr("write")(decoded(text.data(), text.size()));
      out.attr("flush")();
    }
  } else {
    for (std::size_t begin = 0; begin < text.size();) {
      std::size_t stop = text.find('\n', begin);
      if (stop == std::string::npos) stop = text.size();
      sink_(decoded(text.data() + begin, stop - begin));
      begin = stop + 1;
    }
  }
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

}  // namespace dem::python
