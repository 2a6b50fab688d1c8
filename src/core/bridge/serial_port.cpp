#include "icanc/core/bridge/serial_port.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

namespace icanc {

namespace {

speed_t speedOf(int baud) {
  switch (baud) {
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    case 460800: return B460800;
    case 500000: return B500000;
    case 921600: return B921600;
    default: return B0;
  }
}

std::string errnoText(const char* what) { return std::string(what) + ": " + std::strerror(errno); }

}  // namespace

bool SerialPort::baudSupported(int baud) { return speedOf(baud) != B0; }

SerialPort::~SerialPort() { close(); }

bool SerialPort::open(const std::string& path, int baud, std::string& error) {
  close();
  if (!baudSupported(baud)) {
    error = "unsupported baud rate " + std::to_string(baud);
    return false;
  }
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    error = errnoText(("open " + path).c_str());
    return false;
  }
  termios tio;
  if (tcgetattr(fd, &tio) != 0) {
    error = errnoText(("tcgetattr " + path + " (not a serial port?)").c_str());
    ::close(fd);
    return false;
  }
  cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~(CSTOPB | PARENB | CRTSCTS);
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  cfsetispeed(&tio, speedOf(baud));
  cfsetospeed(&tio, speedOf(baud));
  if (tcsetattr(fd, TCSANOW, &tio) != 0) {
    error = errnoText(("tcsetattr " + path).c_str());
    ::close(fd);
    return false;
  }
  tcflush(fd, TCIOFLUSH);  // bytes from before the open belong to nobody
  struct stat st;
  device_ = fstat(fd, &st) == 0 ? static_cast<unsigned long long>(st.st_rdev) : 0;
  fd_ = fd;
  path_ = path;
  return true;
}

void SerialPort::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

long SerialPort::read(std::uint8_t* buffer, std::size_t capacity, double timeout_s, std::string& error) {
  if (fd_ < 0) {
    error = "port not open";
    return -1;
  }
  pollfd p{fd_, POLLIN, 0};
  const int timeout_ms = static_cast<int>(std::ceil(std::max(0.0, timeout_s) * 1000.0));
  const int n = ::poll(&p, 1, timeout_ms);
  if (n < 0) {
    if (errno == EINTR) return 0;
    error = errnoText("poll");
    return -1;
  }
  if (n == 0) return 0;
  if (p.revents & POLLIN) {
    const ssize_t got = ::read(fd_, buffer, capacity);
    if (got > 0) return static_cast<long>(got);
    if (got < 0 && (errno == EAGAIN || errno == EINTR)) return 0;
    error = got == 0 ? std::string("end of file (device gone)") : errnoText("read");
    return -1;
  }
  if (p.revents & (POLLHUP | POLLERR | POLLNVAL)) {
    error = (p.revents & POLLHUP) ? "hang-up (device gone)" : "port error";
    return -1;
  }
  return 0;
}

bool SerialPort::write(const std::uint8_t* data, std::size_t size, bool drain, std::string& error) {
  if (fd_ < 0) {
    error = "port not open";
    return false;
  }
  std::size_t done = 0;
  int stalls = 0;
  while (done < size) {
    const ssize_t n = ::write(fd_, data + done, size - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EAGAIN && ++stalls <= 100) {  // output buffer full: wait for room
      pollfd p{fd_, POLLOUT, 0};
      ::poll(&p, 1, 10);
      continue;
    }
    error = n < 0 && errno == EAGAIN ? std::string("write stalled for 1 s (device not reading)")
                                     : errnoText("write");
    return false;
  }
  if (drain && tcdrain(fd_) != 0 && errno != EINTR) {
    error = errnoText("tcdrain");
    return false;
  }
  return true;
}

bool SerialPort::stillPresent() const {
  if (fd_ < 0) return false;
  struct stat st;
  if (::stat(path_.c_str(), &st) != 0) return false;
  return static_cast<unsigned long long>(st.st_rdev) == device_;
}

}  // namespace icanc
