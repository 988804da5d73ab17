#include <dem/io/folder_lock.hpp>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <dem/core/errors.hpp>

namespace dem::io {

namespace {

std::string read_all(int fd) {
  std::string text;
  char buffer[512];
  ::lseek(fd, 0, SEEK_SET);
  for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) > 0;) text.append(buffer, static_cast<std::size_t>(n));
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  return text;
}

std::string now_utc() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

}  // namespace

FolderLock::FolderLock(const std::filesystem::path& folder, const std::string& lock_name, const std::string& program) {
  const std::string where = "output folder " + folder.string();
  const std::filesystem::path lock_file = folder / lock_name;
  fd_ = ::open(lock_file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw InputError(where + " is not writable (" + std::strerror(errno) + ")");
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const std::string holder = read_all(fd_);
    ::close(fd_);
    fd_ = -1;
    throw InputError(where + " is in use by another run (" + (holder.empty() ? std::string("starting") : holder) +
                     "): wait until it ends, or choose another folder");
  }
  const std::string holder = "pid " + std::to_string(::getpid()) + ", " + program + ", started " + now_utc() + "\n";
  const bool recorded = ::ftruncate(fd_, 0) == 0 && ::lseek(fd_, 0, SEEK_SET) == 0 &&
                        ::write(fd_, holder.data(), holder.size()) == static_cast<ssize_t>(holder.size());
  if (!recorded) {
    const std::string reason = std::strerror(errno);
    ::close(fd_);
    fd_ = -1;
    throw InputError(where + " is not writable (" + reason + ")");
  }
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock; the file stays, read only while locked
}

}  // namespace dem::io
