#include <iostream>

#include "net/beast.hpp"

namespace pslam::server {

void Fail(beast::error_code ec, const char* what) {
  // A peer that goes away (a closed browser tab, a stopped agent) is normal, not an error.
  if (ec == net::error::operation_aborted || ec == websocket::error::closed || ec == net::error::eof ||
      ec == beast::error::timeout || ec == net::error::connection_reset || ec == http::error::end_of_stream ||
      ec == net::error::not_connected || ec == net::error::broken_pipe || ec == net::error::connection_aborted) {
    return;
  }
  std::cerr << what << ": " << ec.message() << "\n";
}

}  // namespace pslam::server
