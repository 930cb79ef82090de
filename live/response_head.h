// The head of a response that ends its connection says so once: exactly one
// "Connection: close" and no Keep-Alive. cpp-httplib writes a Keep-Alive
// header on any response whose request did not say "close" (also when the
// handler's response does), and a second Connection header when both did;
// the server rewrites the head as it goes out (connection_stream.h).
#pragma once

#include <string>
#include <string_view>

namespace pt::live {

/// Whether `head` (a status line and header lines, through the blank line) has a "Connection: close" header
/// (the name in any case).
bool head_closes_connection(std::string_view head);

/// `head` with its Connection and Keep-Alive headers replaced by one "Connection: close" where the first of
/// them was, when it closes the connection; otherwise `head` unchanged.
std::string closing_head(std::string_view head);

}  // namespace pt::live
