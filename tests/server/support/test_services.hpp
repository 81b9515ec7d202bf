#pragma once
// Real PostgreSQL and Redis servers for tests, from deploy/cluster/services.sh: on loopback, data in
// a temporary directory. Under ctest one pair serves every test (a fixture starts it and sets
// PSLAM_TEST_SERVICES_DIR); a test binary run by hand starts its own pair once and stops it at
// exit. Each test gets a database of its own.
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>


namespace pslam::server::testing {

inline std::filesystem::path ServicesScript() { return std::filesystem::path(PSLAM_SOURCE_DIR) / "deploy/cluster/services.sh"; }

inline std::string ReadUrl(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string url;
  std::getline(in, url);
  if (url.empty()) throw std::runtime_error("no URL in " + file.string() + ": are the test services running?");
  return url;
}

// The state directory of the running services, starting them for this process if needed.
inline std::filesystem::path TestServicesDir() {
  static const std::filesystem::path dir = [] {
    if (const char* shared = std::getenv("PSLAM_TEST_SERVICES_DIR")) return std::filesystem::path(shared);
    const auto own = std::filesystem::temp_directory_path() / ("pslam-services-" + std::to_string(getpid()));
    const std::string start = ServicesScript().string() + " start " + own.string() + " >/dev/null";
    if (std::system(start.c_str()) != 0) throw std::runtime_error("cannot start the test services: " + start);
    static const std::string stop = ServicesScript().string() + " stop " + own.string() + " >/dev/null 2>&1";
    std::atexit([] { (void)std::system(stop.c_str()); });
    return own;
  }();
  return dir;
}

inline std::string TestPostgresUrl() { return ReadUrl(TestServicesDir() / "postgres.url"); }

// Runs one SQL statement of ours (no user input) with psql, the server's own client.
inline void RunPsql(const std::string& url, const std::string& sql) {
  const std::string command = "PGOPTIONS='-c client_min_messages=warning' psql -q -v ON_ERROR_STOP=1 '" + url + "' -c '" + sql + "' >/dev/null";
  if (std::system(command.c_str()) != 0) throw std::runtime_error("failed: " + command);
}
inline std::string TestRedisUrl() { return ReadUrl(TestServicesDir() / "redis.url"); }

// A fresh, empty PostgreSQL database for one test, dropped at scope exit.
class TestPostgresDatabase {
 public:
  TestPostgresDatabase() {
    static std::atomic<int> counter{0};
    name_ = "pslam_test_" + std::to_string(getpid()) + "_" + std::to_string(counter++);
    const std::string admin = TestPostgresUrl();
    url_ = admin.substr(0, admin.rfind('/') + 1) + name_;
    RunPsql(admin, "DROP DATABASE IF EXISTS " + name_);  // names are ours: digits and underscores
    RunPsql(admin, "CREATE DATABASE " + name_);
    admin_ = admin;
  }
  ~TestPostgresDatabase() {
    try {
      RunPsql(admin_, "DROP DATABASE IF EXISTS " + name_ + " WITH (FORCE)");
    } catch (const std::exception&) {
    }
  }
  TestPostgresDatabase(const TestPostgresDatabase&) = delete;
  TestPostgresDatabase& operator=(const TestPostgresDatabase&) = delete;
  const std::string& url() const { return url_; }

 private:
  std::string name_, url_, admin_;
};

}  // namespace pslam::server::testing
