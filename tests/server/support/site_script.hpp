#pragma once
// Sites for the tests: creating one, mapping the synthetic room into it through a real session,
// and the room's true map drawn as map_server files by the test itself (not by the server's code).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "common/base64.hpp"
#include "server/support/agent_script.hpp"
#include "server/support/clients.hpp"

namespace pslam::server::testing {

inline std::string CreateSite(unsigned short port, const std::string& name) {
  const auto r = Post(port, "/api/sites", nlohmann::json{{"name", name}}.dump());
  if (r.status != 201) throw std::runtime_error("creating a site: " + r.body);
  return r.Json()["id"];
}

// Maps 'scans' scans of the scripted robot in a session of 'site', closes it; returns its id.
inline std::string MapRoomSession(unsigned short port, const std::string& site, int scans = 120) {
  WsClient agent(port, "/api/ingest");
  agent.SendJson(Hello("new", {{"particles", 4}, {"seed", 7}, {"site", site}}));
  const std::string id = (*agent.ReadType("welcome"))["session_id"];
  for (std::int64_t seq = 1; seq <= scans; ++seq) SendScan(agent, seq, seq % 2 == 1);
  if (WaitForAck(agent, scans) != scans) throw std::runtime_error("the mapping session did not take every scan");
  if (Post(port, "/api/sessions/" + id + "/close", "").status != 200) throw std::runtime_error("closing failed");
  return id;
}

// The synthetic room's true map at 5 cm: walls occupied (0), the inside free (254), the rest
// unknown (205); a P5 PGM with a comment of its own, and its YAML.
struct MapFiles {
  std::string yaml;
  std::string pgm;
};

inline MapFiles TrueRoomMap() {
  constexpr double kRes = 0.05;
  constexpr int kWidth = 240, kHeight = 200;  // 12 m x 10 m around the 10 m x 8 m room
  constexpr double kOriginX = -6.0, kOriginY = -5.0;
  const auto walls = ::pslam::testing::RoomWalls();
  const auto near_wall = [&](const Eigen::Vector2d& p) {
    for (const auto& w : walls) {
      const Eigen::Vector2d e = w.b - w.a;
      const double t = std::clamp((p - w.a).dot(e) / e.squaredNorm(), 0.0, 1.0);
      if ((w.a + t * e - p).norm() <= kRes * 0.75) return true;
    }
    return false;
  };
  std::string pixels(static_cast<std::size_t>(kWidth * kHeight), static_cast<char>(205));
  for (int row = 0; row < kHeight; ++row) {
    for (int col = 0; col < kWidth; ++col) {
      const Eigen::Vector2d p(kOriginX + (col + 0.5) * kRes, kOriginY + (kHeight - 1 - row + 0.5) * kRes);
      const bool inside = p.x() > -4.987 && p.x() < 5.013 && p.y() > -3.979 && p.y() < 4.021;
      char& px = pixels[static_cast<std::size_t>(row * kWidth + col)];
      if (near_wall(p)) px = 0;
      else if (inside) px = static_cast<char>(254);
    }
  }
  MapFiles f;
  f.pgm = "P5\n# drawn by the test\n" + std::to_string(kWidth) + " " + std::to_string(kHeight) + "\n255\n" + pixels;
  f.yaml = "image: room.pgm\nresolution: 0.05\norigin: [-6.0, -5.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\n"
           "free_thresh: 0.196\n";
  return f;
}

inline HttpResult ImportMap(unsigned short port, const std::string& site, const MapFiles& files) {
  return Post(port, "/api/sites/" + site + "/maps",
              nlohmann::json{{"yaml", files.yaml}, {"pgm_base64", Base64Encode(files.pgm)}, {"note", "true map"}}.dump());
}

}  // namespace pslam::server::testing
