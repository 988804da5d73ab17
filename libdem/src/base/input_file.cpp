#include <dem/base/input_file.hpp>

#include <dem/base/errors.hpp>

namespace dem {

namespace {

// What the path is, when it is not a regular file.
std::string kind_of(const std::filesystem::file_status& status) {
  switch (status.type()) {
    case std::filesystem::file_type::not_found: return "does not exist";
    case std::filesystem::file_type::directory: return "is a folder";
    case std::filesystem::file_type::fifo: return "is a FIFO (named pipe)";
    case std::filesystem::file_type::character: return "is a character device";
    case std::filesystem::file_type::block: return "is a block device";
    case std::filesystem::file_type::socket: return "is a socket";
    default: return "is not a regular file";
  }
}

}  // namespace

void require_input_file(const std::filesystem::path& path, const std::string& what, const std::string& allowed,
                        std::uintmax_t max_bytes) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  const std::string head = what + " = " + path.string() + ": ";
  if (error && status.type() != std::filesystem::file_type::not_found)
    throw InputError(head + "cannot be read (" + error.message() + "); must be " + allowed);
  if (status.type() != std::filesystem::file_type::regular) throw InputError(head + kind_of(status) + "; must be " + allowed);
  const std::uintmax_t bytes = std::filesystem::file_size(path, error);
  if (!error && bytes > max_bytes)
    throw InputError(head + std::to_string(bytes) + " bytes; must be " + allowed + " of at most " + std::to_string(max_bytes) +
                     " bytes");
}

}  // namespace dem
