// Asio's and Beast's non-template code, compiled once for the whole project instead of inline in
// every file that includes them (BOOST_ASIO_SEPARATE_COMPILATION, BOOST_BEAST_SEPARATE_COMPILATION:
// see CMakeLists.txt). Beast's permessage-deflate alone is a zlib implementation in headers.
#include <utility>  // Boost 1.74 asio/awaitable.hpp uses std::exchange without including it

#include <boost/asio/impl/src.hpp>
#include <boost/beast/src.hpp>
