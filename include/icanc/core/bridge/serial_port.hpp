// A raw serial port (POSIX termios), 8N1 without flow control, as the headlight bridge needs it:
// reads that wait with a timeout, writes that return once the bytes are on the wire (tcdrain),
// and a port that disappears (USB unplugged, pseudo-terminal closed) reported as an error instead
// of a silent stall. Plain termios rather than a serial library so that a hang-up is seen at once
// (poll's POLLHUP / EIO) and the caller can tell "no data" from "port gone".
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace icanc {

class SerialPort {
 public:
  SerialPort() = default;
  ~SerialPort();
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  // Baud rates the port accepts (9600 ... 921600; the bridge defaults to 57600).
  static bool baudSupported(int baud);

  // Opens `path` (a device or a symlink to one) raw at `baud`. False with `error` set on failure.
  bool open(const std::string& path, int baud, std::string& error);
  void close();
  bool isOpen() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }

  // Waits up to timeout_s for input and reads what is there (at most `capacity` bytes).
  // Returns the byte count (0: nothing within the timeout), or -1 when the port is gone or
  // failed (`error` says why; the caller closes it).
  long read(std::uint8_t* buffer, std::size_t capacity, double timeout_s, std::string& error);
  // Writes all bytes, then waits until they are transmitted when `drain`. False on failure.
  bool write(const std::uint8_t* data, std::size_t size, bool drain, std::string& error);
  // False when the opened path no longer exists or now names another device (replugged
  // elsewhere); cheap, for a periodic check.
  bool stillPresent() const;

 private:
  int fd_ = -1;
  std::string path_;
  unsigned long long device_ = 0;  // st_rdev of the opened device
};

}  // namespace icanc
