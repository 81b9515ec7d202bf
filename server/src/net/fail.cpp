#include <iostream>

#include "net/beast.hpp"

namespace pslam::server {

void Fail(beast::error_code ec, const char* what) {
  if (ec == net::error::operation_aborted || ec == websocket::error::closed || ec == net::error::eof ||
      ec == beast::error::timeout || ec == net::error::connection_reset || ec == http::error::end_of_stream) {
    return;
  }
  std::cerr << what << ": " << ec.message() << "\n";
}

}  // namespace pslam::server
