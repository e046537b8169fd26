#pragma once
// Internal: MRPT exception texts carry stacked messages and call-stack dumps; messages for users
// keep the "Message:" lines only.

#include <string>

namespace rasm::io::detail {

/// "msg1 <- msg2" from the "Message:" lines of an MRPT exception text, else its first line;
/// printable ASCII (see printable()).
std::string shortMrptMessage(const std::string& what);

/// Text from a file (sensor labels, class names a corrupt rawlog makes MRPT quote) made safe for
/// messages and report.json: bytes outside printable ASCII become "\xNN".
std::string printable(const std::string& text);

}  // namespace rasm::io::detail
