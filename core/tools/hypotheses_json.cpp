#include "hypotheses_json.hpp"

#include <cmath>
#include <fstream>
#include <stdexcept>

namespace pslam {
namespace {

std::string Number(double v) {
  if (!std::isfinite(v)) return "null";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

}  // namespace

void WriteHypothesesJson(const std::string& path, const PSlam& slam) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  const double resolution = slam.options().filter.resolution;
  out << "{\"resolution\": " << Number(resolution) << ", \"hypotheses\": [";
  bool first = true;
  for (const Hypothesis& h : slam.hypotheses()) {
    out << (first ? "\n" : ",\n") << "  {\"id\": " << h.id << ", \"time\": " << Number(h.time)
        << ", \"target_cell\": [" << h.target_cell.x() << ", " << h.target_cell.y() << "]"
        << ", \"reference_cell\": [" << h.reference_cell.x() << ", " << h.reference_cell.y() << "]"
        << ", \"theta\": " << Number(h.theta) << ", \"translation\": [" << Number(h.translation.x()) << ", "
        << Number(h.translation.y()) << "]"
        << ", \"psi\": " << Number(h.psi) << ", \"area_m2\": " << Number(h.area_m2)
        << ", \"status\": \"" << StatusName(h.status) << "\", \"hit_ratio\": " << Number(h.hit_ratio)
        << ", \"psi_observed\": " << Number(h.psi_observed) << ", \"cells_remaining\": " << h.cells.size() << "}";
    first = false;
  }
  out << "\n], \"history\": [";
  first = true;
  for (const HypothesisEvent& e : slam.history()) {
    out << (first ? "\n" : ",\n") << "  {\"id\": " << e.id << ", \"time\": " << Number(e.time) << ", \"status\": \""
        << StatusName(e.status) << "\"}";
    first = false;
  }
  out << "\n]}\n";
  if (!out) throw std::runtime_error("failed writing " + path);
}

}  // namespace pslam
