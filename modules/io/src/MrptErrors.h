#pragma once
// Internal: MRPT exception texts carry stacked messages and call-stack dumps; messages for users
// keep the "Message:" lines only.

#include <string>

namespace rasm::io::detail {

/// "msg1 <- msg2" from the "Message:" lines of an MRPT exception text, else its first line.
std::string shortMrptMessage(const std::string& what);

}  // namespace rasm::io::detail
