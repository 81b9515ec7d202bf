#include "pslam/localize/monte_carlo_localizer.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "pslam/common/random.hpp"
#include "pslam/filter/motion_model.hpp"
#include "pslam/filter/resampling.hpp"
#include "pslam/sensor/scan_points.hpp"

namespace pslam {
namespace {

// One random stream per step and purpose, derived from (seed, step, purpose); the particles draw
// from it in turn. (The mapping filter gives each particle a stream of its own, since it weighs
// them on several threads; seeding one per particle cost more here than the draws.)
enum Stream : std::uint64_t { kStart = 1, kMotion = 2, kResample = 3, kInjection = 4 };
// Standard deviations (m, m, rad) of the particles drawn around a place the search found.
const Eigen::Vector3d kPlaceSpread(0.05, 0.05, 0.03);

double LogAddExp(double a, double b) {
  const double top = std::max(a, b);
  if (top == -INFINITY) return top;
  return top + std::log(std::exp(a - top) + std::exp(b - top));
}

// The running average w += alpha (w_avg - w), in log space.
double BlendLog(double log_w, double log_avg, double alpha) {
  if (alpha <= 0.0) return log_w;
  if (alpha >= 1.0) return log_avg;
  return LogAddExp(std::log1p(-alpha) + log_w, std::log(alpha) + log_avg);
}

bool MovedEnough(const Pose2D& delta, const MclOptions& o) {
  return std::hypot(delta.x, delta.y) >= o.update_min_d || std::abs(delta.theta) >= o.update_min_a;
}

}  // namespace

MonteCarloLocalizer::MonteCarloLocalizer(const OccupancyGrid& map, const MclOptions& options)
    : options_(options),
      field_([&]() -> const OccupancyGrid& {
        if (const std::string problem = ValidateMclOptions(options); !problem.empty())
          throw std::invalid_argument(problem);
        return map;
      }(), options.likelihood),
      scan_odometry_(options.scan_odometry),
      resolution_(map.resolution()) {
  const CellBox known = map.KnownBounds();
  for (int y = known.min.y(); y <= known.max.y(); ++y) {
    for (int x = known.min.x(); x <= known.max.x(); ++x) {
      const OccupancyGrid::Cell c = map.At(x, y);
      if (c != OccupancyGrid::kUnknown && CellProbability(c) < kFreeCellProbability) free_cells_.emplace_back(x, y);
    }
  }
  if (free_cells_.empty()) throw std::invalid_argument("the map has no free cell to localize in");
  if (options_.place.enabled) places_.emplace(map, options_.place);
}

Pose2D MonteCarloLocalizer::RandomFreePose(std::mt19937_64& rng) const {
  std::uniform_int_distribution<std::size_t> pick(0, free_cells_.size() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Eigen::Vector2i c = free_cells_[pick(rng)];
  return {(c.x() + unit(rng)) * resolution_, (c.y() + unit(rng)) * resolution_,
          (2.0 * unit(rng) - 1.0) * std::numbers::pi};
}

void MonteCarloLocalizer::Reset(std::vector<Pose2D> poses) {
  poses_ = std::move(poses);
  log_weights_.assign(poses_.size(), 0.0);
  initialized_ = true;
  force_update_ = true;
  averaged_ = 0;
  ++step_;
  last_.searching = false;
  last_.place = PlaceMatch{};
  look_alikes_drawn_ = false;
  Summarize();
}

void MonteCarloLocalizer::SetPose(const Pose2D& mean, const Eigen::Matrix3d& covariance) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  if (!covariance.allFinite() || !mean.translation().allFinite() || !std::isfinite(mean.theta) ||
      (covariance - covariance.transpose()).cwiseAbs().maxCoeff() > 1e-9 || eigen.eigenvalues().minCoeff() < -1e-12) {
    throw std::invalid_argument("the initial pose needs a finite mean and a symmetric positive semi-definite covariance");
  }
  const Eigen::Matrix3d root =
      eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * eigen.eigenvectors().transpose();
  Reset(DrawAround({mean}, root));
}

std::vector<Pose2D> MonteCarloLocalizer::DrawAround(const std::vector<Pose2D>& centres, const Eigen::Matrix3d& root) {
  std::vector<Pose2D> poses(static_cast<std::size_t>(options_.max_particles));
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::mt19937_64 rng = MakeStream(options_.seed, step_, kStart);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Pose2D& centre = centres[i % centres.size()];
    const Eigen::Vector3d z(gauss(rng), gauss(rng), gauss(rng));
    const Eigen::Vector3d d = root * z;
    poses[i] = Pose2D(centre.x + d.x(), centre.y + d.y(), centre.theta + d.z());
  }
  return poses;
}

void MonteCarloLocalizer::StartGlobal() {
  std::vector<Pose2D> poses(static_cast<std::size_t>(options_.max_particles));
  std::mt19937_64 rng = MakeStream(options_.seed, step_, kStart);
  for (Pose2D& pose : poses) pose = RandomFreePose(rng);
  Reset(std::move(poses));
  if (places_) {
    places_->Reset();
    last_.searching = true;
    last_.localized = false;
  }
}

std::vector<double> MonteCarloLocalizer::weights() const { return NormalizeLogWeights(log_weights_); }

void MonteCarloLocalizer::Weigh(const std::vector<Eigen::Vector2f>& points) {
  const std::vector<double> prior = weights();
  const double inv_temperature = 1.0 / options_.likelihood.temperature;
  const double inv_points = 1.0 / static_cast<double>(points.size());
  // How well the cloud explains the scan, for augmented MCL: sum_i prior_i * (geometric mean of
  // the beam scores of particle i). Per beam, so that it keeps one scale from scan to scan (AMCL
  // sums beam scores for the same reason): the product over all beams swings by orders of
  // magnitude between places, and the averages would read every such swing as a kidnapping.
  double log_avg = -INFINITY;
  for (std::size_t i = 0; i < poses_.size(); ++i) {
    const double log_likelihood = field_.LogLikelihood(points, poses_[i]);
    log_weights_[i] += log_likelihood * inv_temperature;
    if (prior[i] > 0.0) log_avg = LogAddExp(log_avg, std::log(prior[i]) + log_likelihood * inv_points);
  }
  // The k-th average since a start weighs its sample by max(alpha, 1 / k): a plain mean until
  // 1 / alpha samples are in. Started from the first sample alone, the slow average would stay
  // near the poor fit of a fresh, spread-out cloud for a thousand updates, and a later kidnapping
  // would not show against it.
  ++averaged_;
  const double share = 1.0 / static_cast<double>(averaged_);
  log_w_slow_ = BlendLog(log_w_slow_, log_avg, options_.recovery_alpha_slow > 0.0 ? std::max(options_.recovery_alpha_slow, share) : 0.0);
  log_w_fast_ = BlendLog(log_w_fast_, log_avg, options_.recovery_alpha_fast > 0.0 ? std::max(options_.recovery_alpha_fast, share) : 0.0);
}

void MonteCarloLocalizer::Resample() {
  const std::vector<double> w = weights();
  std::mt19937_64 rng = MakeStream(options_.seed, step_, kResample);
  // KLD: the bins a full-size draw from the posterior occupies set the count. Drawing max_particles
  // first and counting afterwards, rather than stopping a draw early as Fox does, keeps the draw
  // low-variance (a systematic comb cut short would cover only part of the weights).
  const std::vector<int> full = SystematicResample(w, rng, options_.max_particles);
  std::vector<Pose2D> drawn(full.size());
  for (std::size_t i = 0; i < full.size(); ++i) drawn[i] = poses_[static_cast<std::size_t>(full[i])];
  const PoseBinning binning{options_.bin_size_xy, options_.bin_size_theta};
  const int count = KldSampleCount(CountOccupiedBins(drawn, binning), options_.kld_err, options_.kld_z,
                                   options_.min_particles, options_.max_particles);
  const std::vector<int> picks = SystematicResample(w, rng, count);
  const double inject = last_.injection_probability;
  std::vector<Pose2D> next(picks.size());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int injected = 0;
  std::mt19937_64 slot_rng = MakeStream(options_.seed, step_, kInjection);
  for (std::size_t i = 0; i < picks.size(); ++i) {
    next[i] = poses_[static_cast<std::size_t>(picks[i])];
    if (inject <= 0.0) continue;
    if (unit(slot_rng) >= inject) continue;
    next[i] = RandomFreePose(slot_rng);
    ++injected;
  }
  poses_ = std::move(next);
  log_weights_.assign(poses_.size(), 0.0);
  last_.resampled = true;
  last_.injected = injected;
  ++stats_.resamplings;
  stats_.injected += injected;
}

void MonteCarloLocalizer::Summarize() {
  const std::vector<double> w = weights();
  const std::vector<ParticleCluster> clusters =
      ClusterParticles(poses_, w, PoseBinning{options_.bin_size_xy, options_.bin_size_theta});
  last_.clusters = static_cast<int>(clusters.size());
  last_.cluster = clusters.empty() ? ParticleCluster{} : clusters.front();
  last_.estimate = last_.cluster.mean;
  last_.particles = static_cast<int>(poses_.size());
  stats_.min_particles_seen = stats_.min_particles_seen == 0 ? last_.particles : std::min(stats_.min_particles_seen, last_.particles);
  stats_.max_particles_seen = std::max(stats_.max_particles_seen, last_.particles);
  last_.localized = last_.cluster.weight >= options_.localized_weight &&
                    last_.cluster.position_std <= options_.localized_position_std &&
                    last_.cluster.heading_std <= options_.localized_heading_std;
}

MclUpdate MonteCarloLocalizer::AddScan(const LaserScan& scan) {
  if (!initialized_) StartGlobal();
  ++stats_.scans;
  last_.updated = last_.resampled = false;
  last_.injected = 0;
  // Between updates the estimate moves by odometry: the wheels' own, or corrected by matching the
  // scan against the scans before it (scan_odometry.hpp).
  const Pose2D odometry = options_.scan_odometry.enabled ? scan_odometry_.Correct(scan) : scan.odometry;
  if (!have_odometry_) {
    update_odometry_ = odometry;
    have_odometry_ = true;
  }
  const Pose2D delta = Between(update_odometry_, odometry);
  // The scan's endpoints in the robot frame, for weighing, refining and the place search alike.
  const std::vector<Eigen::Vector2f> hits = ToScanPoints(scan, options_.points).hits;
  if (!force_update_ && !MovedEnough(delta, options_)) {
    last_.estimate = last_.cluster.mean * delta;  // between updates, odometry carries the estimate
    RefineEstimate(hits, odometry);
    SearchPlace(hits, odometry);
    return last_;
  }
  ++step_;
  std::mt19937_64 rng = MakeStream(options_.seed, step_, kMotion);
  for (Pose2D& pose : poses_) pose = pose * SampleMotion(delta, options_.motion, rng);
  update_odometry_ = odometry;
  force_update_ = false;
  const std::vector<Eigen::Vector2f> points = SelectEvenly(hits, options_.likelihood.max_beams);
  if (!points.empty()) Weigh(points);
  last_.updated = true;
  last_.effective_sample_size = EffectiveSampleSize(weights());
  const double drop = averaged_ > 0 ? 1.0 - std::exp(log_w_fast_ - log_w_slow_) : 0.0;
  last_.injection_probability = drop > options_.recovery_min_drop ? drop : 0.0;
  // Injection happens at resampling, so a cloud that fits worse than it used to is resampled even
  // when its weights are even (a kidnapped cloud is uniformly wrong).
  if (last_.effective_sample_size < options_.resample_threshold * static_cast<double>(poses_.size()) ||
      last_.injection_probability > 0.0) {
    Resample();
  }
  // The fit dropped as after a kidnapping: the place is searched for again, from the scans after
  // the drop (odometry does not know where the robot was carried).
  if (last_.injection_probability > 0.0 && places_ && !last_.searching) {
    places_->Reset();
    last_.searching = true;
    look_alikes_drawn_ = false;
  }
  ++stats_.updates;
  Summarize();
  RefineEstimate(hits, odometry);
  SearchPlace(hits, odometry);
  if (options_.fill_unknown && last_.localized && !last_.searching) FillUnknown(hits);
  return last_;
}

void MonteCarloLocalizer::FillUnknown(const std::vector<Eigen::Vector2f>& hits) {
  const Pose2D& pose = last_.estimate;
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  const Eigen::Vector2d sensor(pose.x, pose.y);
  std::vector<Eigen::Vector2d> unmapped;
  int checked = 0, agreeing = 0;
  for (const auto& p : hits) {
    const Eigen::Vector2d world(pose.x + c * p.x() - s * p.y(), pose.y + s * p.x() + c * p.y());
    if (const std::optional<bool> explained = field_.ExplainedByMap(world)) {
      ++checked;
      agreeing += *explained;
    } else if (field_.BeamBlocked(sensor, world)) {
      ++checked;  // through a wall: disagrees
    } else {
      unmapped.push_back(world);
    }
  }
  // Where the map disagrees with the scan, the pose is wrong (the robot was carried off and the
  // fit has not dropped yet) or the map is: either way, what is drawn now would be drawn wrongly,
  // and would let a wrong pose explain its scans.
  if (checked >= options_.fill_min_checked && agreeing < options_.fill_min_agreement * checked) return;
  for (const Eigen::Vector2d& w : unmapped) field_.AddUnmappedObstacle(w);
}

void MonteCarloLocalizer::SearchPlace(const std::vector<Eigen::Vector2f>& hits, const Pose2D& odometry) {
  if (!last_.searching) return;
  places_->Add(hits, odometry);
  if (places_->SearchDue()) last_.place = places_->Search();
  if (last_.place.outcome == PlaceMatch::Outcome::kUnique) {
    // Tracking starts at the recognized place, fitted to this scan on the full-resolution field.
    const PlaceMatch match = last_.place;
    const std::vector<Eigen::Vector2f> points = SelectEvenly(hits, options_.refine_max_points);
    const Pose2D place = points.empty() ? match.pose : field_.Refine(points, match.pose, 2.0 * options_.place.search_resolution, 0.05);
    SetPose(place, kPlaceSpread.cwiseProduct(kPlaceSpread).asDiagonal());
    update_odometry_ = odometry;  // the particles stand at this scan's pose
    last_.estimate = place;
    last_.place = match;
    return;
  }
  if (options_.track_look_alikes && last_.place.outcome == PlaceMatch::Outcome::kAmbiguous && !look_alikes_drawn_) {
    DrawAroundLookAlikes(last_.place, odometry);
    return;
  }
  if (look_alikes_drawn_) {
    // The particles stand around the candidates and weigh them as the robot drives, so the
    // estimate is most often at the right one well before the search can tell; being localized
    // is still the search's to say: a cluster's share of the weight is no proof (resampling lets
    // one of two equal places win by chance).
    last_.localized = false;
    return;
  }
  // Until a place is recognized, the particles' agreement is no proof: a spread cloud settles on a
  // look-alike place as readily as on the right one. Only where no place explains the last metres
  // (a map that lacks what the robot sees) is their verdict all there is.
  if (last_.place.outcome != PlaceMatch::Outcome::kNone || !places_->searched()) last_.localized = false;
}

void MonteCarloLocalizer::DrawAroundLookAlikes(const PlaceMatch& match, const Pose2D& odometry) {
  const Eigen::Matrix3d root = kPlaceSpread.asDiagonal();
  Reset(DrawAround({match.pose, match.rival}, root));
  update_odometry_ = odometry;  // the particles stand at this scan's pose
  last_.searching = true;       // the search goes on: a unique place still settles it
  last_.place = match;
  last_.localized = false;
  look_alikes_drawn_ = true;
}

void MonteCarloLocalizer::RefineEstimate(const std::vector<Eigen::Vector2f>& hits, const Pose2D& odometry) {
  if (!options_.refine || !last_.localized) {
    report_.reset();
    return;
  }
  const std::vector<Eigen::Vector2f> points = SelectEvenly(hits, options_.refine_max_points);
  const Pose2D cloud = last_.estimate;
  Pose2D refined = cloud;  // a scan with no return fits nothing: the report is pulled toward the cloud
  if (!points.empty()) {
    // The cloud is the prior; the scan weighs as much as in an update of the filter.
    RefinePrior prior;
    const double floor = 1e-4;  // (1 cm)^2, so that a collapsed cloud does not pin the pose
    prior.position_information = (last_.cluster.position_covariance + floor * Eigen::Matrix2d::Identity()).inverse();
    prior.heading_information = 1.0 / (last_.cluster.heading_std * last_.cluster.heading_std + 1e-5);
    prior.likelihood_weight = static_cast<double>(std::min<std::size_t>(points.size(), options_.likelihood.max_beams)) /
                              (static_cast<double>(points.size()) * options_.likelihood.temperature);
    refined = field_.Refine(points, cloud, options_.refine_max_shift, options_.refine_max_turn, 0.002, prior);
  }
  const Pose2D predicted = report_ ? *report_ * Between(report_odometry_, odometry) : refined;
  // A report that has fallen as far behind the cloud as a fit may move (the cloud jumped to a
  // recognized place) restarts at the fit.
  const bool behind = std::hypot(predicted.x - cloud.x, predicted.y - cloud.y) > options_.refine_max_shift ||
                      std::abs(NormalizeAngle(predicted.theta - cloud.theta)) > options_.refine_max_turn;
  if (report_ && !behind) {
    // The last report moved by odometry, pulled toward this scan's fit by the gain.
    const double k = options_.refine_gain;
    last_.estimate = Pose2D(predicted.x + k * (refined.x - predicted.x), predicted.y + k * (refined.y - predicted.y),
                            predicted.theta + k * NormalizeAngle(refined.theta - predicted.theta));
  } else {
    last_.estimate = refined;
  }
  report_ = last_.estimate;
  report_odometry_ = odometry;
}

}  // namespace pslam
