/// \file
/// \brief The status codes every firmware and protocol function returns (no exceptions, no errno).
/// Freestanding: <stdint.h> only (the MSP430 has no C++ standard library).
#pragma once

#include <stdint.h>

namespace gyroflip::protocol {

enum class status : uint8_t {
  ok = 0,
  bad_arg = 1,          ///< an argument out of its range (a CONFIGURE value, a buffer too small)
  bad_frame = 2,        ///< a frame that is not well formed (COBS, length, version, type)
  crc_mismatch = 3,     ///< the frame's CRC does not match (corruption, or another message layout)
  overflow = 4,         ///< more bytes than a buffer holds
  timeout = 5,          ///< a device line (RDY) did not come in time
  bus_error = 6,        ///< an SPI/UART transfer failed
  not_supported = 7,    ///< a message or setting this firmware does not have
  busy = 8,             ///< not now: the command needs the device idle (STOP first)
  hw_fault = 9,         ///< the device found a hardware fault (a clock) and does not acquire
  config_mismatch = 10  ///< START named another configuration than the device's (it rebooted)
};

}  // namespace gyroflip::protocol
