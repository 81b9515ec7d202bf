// A mapping session of a site searches the site's stored maps for the references of its
// predictions: a replay of a log in a site whose stored map is an earlier run of the same log gets
// hypotheses whose reference is that stored map, and says so over REST.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <thread>

#include "server/support/clients.hpp"
#include "server/support/server_process.hpp"
#include "server/support/site_script.hpp"
#include "server/support/temp_dir.hpp"
#include "testing/shared_data.hpp"

namespace pslam::server::testing {
namespace {

nlohmann::json WaitClosed(unsigned short port, const std::string& id, int seconds = 300) {
  for (int i = 0; i < seconds * 20; ++i) {
    const auto s = Get(port, "/api/sessions/" + id).Json();
    if (s["status"] != "active") return s;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return Get(port, "/api/sessions/" + id).Json();
}

// Replays 'log' with 'settings' and waits until it has closed; returns the session's id.
std::string Replay(unsigned short port, const std::string& log, const nlohmann::json& settings) {
  const auto r = Post(port, "/api/replays", nlohmann::json{{"log", log}, {"settings", settings}}.dump());
  if (r.status != 201) throw std::runtime_error("replay refused: " + r.body);
  const std::string id = r.Json()["id"];
  if (WaitClosed(port, id)["status"] != "closed") throw std::runtime_error("the replay did not close");
  return id;
}

TEST(SiteLibraryTest, AHypothesisOfASiteSessionTakesItsReferenceFromTheSiteMap) {
  PSLAM_REQUIRE_DATA(log, "intel/intel.clf");
  TempDir dir;
  const auto logs = dir.path() / "logs";
  std::filesystem::create_directories(logs);
  {
    // The first 1500 laser lines of the Intel log and the odometry among them.
    std::ifstream in(log);
    std::ofstream out(logs / "intel-slice.clf");
    std::string line;
    int lasers = 0;
    while (std::getline(in, line) && lasers < 1500) {
      out << line << "\n";
      if (line.rfind("FLASER", 0) == 0) ++lasers;
    }
  }
  ServerProcess server(dir.path() / "data", {"--replay-dir", logs.string()});
  const unsigned short port = server.port();
  const nlohmann::json settings = {{"particles", 4}, {"seed", 3}, {"predictor", {{"similarity_threshold", 0.6}}}};

  // Without a site: the session's own map is every hypothesis's reference.
  const std::string first = Replay(port, "intel-slice.clf", settings);
  const auto own = Get(port, "/api/sessions/" + first + "/hypotheses?limit=1000").Json()["hypotheses"];
  for (const auto& h : own) EXPECT_TRUE(h.value("reference_map", nlohmann::json()).is_null()) << h;

  // Its map becomes the site's first version; a second run in the site searches it.
  const std::string site = CreateSite(port, "intel");
  ASSERT_EQ(Post(port, "/api/sites/" + site + "/maps", nlohmann::json{{"session_id", first}}.dump()).status, 201);
  nlohmann::json in_site = settings;
  in_site["site"] = site;
  const std::string second = Replay(port, "intel-slice.clf", in_site);
  const auto hypotheses = Get(port, "/api/sessions/" + second + "/hypotheses?limit=1000").Json()["hypotheses"];
  int from_site = 0;
  for (const auto& h : hypotheses) {
    if (h.value("reference_map", nlohmann::json()).is_null()) continue;
    EXPECT_EQ(h["reference_map"]["site"], site);
    EXPECT_EQ(h["reference_map"]["version"], 1);
    ++from_site;
    // The stored record says the same as the live one.
    const auto one = Get(port, "/api/sessions/" + second + "/hypotheses/" + std::to_string(h["id"].get<int>())).Json();
    EXPECT_EQ(one["reference_map"], h["reference_map"]);
  }
  std::cout << from_site << " of " << hypotheses.size() << " hypotheses from the site's map\n";
  EXPECT_GT(from_site, 0) << "of " << hypotheses.size() << " hypotheses (" << own.size() << " without the site); "
                          << Get(port, "/api/sessions/" + second + "/stats").Json()["filter"].dump();
}

}  // namespace
}  // namespace pslam::server::testing
