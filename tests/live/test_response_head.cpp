// A response head that closes its connection says so exactly once, without
// Keep-Alive; any other head goes out as it is.
#include <gtest/gtest.h>

#include "live/response_head.h"

namespace pt::live {
namespace {

TEST(ResponseHead, AClosingHeadHasOneConnectionCloseAndNoKeepAlive) {
  const std::string head =
      "HTTP/1.1 403 Forbidden\r\nConnection: close\r\nContent-Length: 3\r\nKeep-Alive: timeout=5, max=1000\r\n"
      "connection: close\r\nX-PT-Error: no\r\n\r\n";
  EXPECT_TRUE(head_closes_connection(head));
  EXPECT_EQ(closing_head(head),
            "HTTP/1.1 403 Forbidden\r\nConnection: close\r\nContent-Length: 3\r\nX-PT-Error: no\r\n\r\n");
  // The name and the value in any case, blanks around the value.
  EXPECT_EQ(closing_head("HTTP/1.1 400 Bad Request\r\nKeep-Alive: timeout=5\r\nCONNECTION:  Close \r\n\r\n"),
            "HTTP/1.1 400 Bad Request\r\nConnection: close\r\n\r\n");
}

TEST(ResponseHead, AnyOtherHeadIsLeftAsItIs) {
  for (const std::string head :
       {"HTTP/1.1 200 OK\r\nKeep-Alive: timeout=5, max=1000\r\nContent-Length: 0\r\n\r\n",
        "HTTP/1.1 200 OK\r\nConnection: keep-alive\r\nKeep-Alive: timeout=5\r\n\r\n",
        "HTTP/1.1 200 OK\r\nX-Connection: close\r\nConnection-Close: 1\r\n\r\n", "HTTP/1.1 100 Continue\r\n\r\n"}) {
    EXPECT_FALSE(head_closes_connection(head)) << head;
    EXPECT_EQ(closing_head(head), head);
  }
}

}  // namespace
}  // namespace pt::live
