#include "app/sim_session.hpp"

#include <cstdio>
#include <system_error>

namespace hrgbench::app {
namespace {

namespace fs = std::filesystem;

std::string RunFileName(int id) {
  char name[32];
  std::snprintf(name, sizeof(name), "runs/run-%03d.csv", id);
  return name;
}

nlohmann::json ToJson(const Eigen::VectorXd& v) {
  nlohmann::json array = nlohmann::json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) array.push_back(v(i));
  return array;
}

bool IsOldSessionFile(const fs::path& dir, const fs::path& entry) {
  if (entry == dir / "session.json") return true;
  const std::string name = entry.filename().string();
  return entry.parent_path() == dir / "runs" && name.starts_with("run-") && name.ends_with(".csv");
}

std::expected<void, std::string> PrepareDirectory(const fs::path& dir, bool force) {
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec))
      return std::unexpected(dir.string() + ": exists and is not a directory");
    if (!fs::is_empty(dir, ec)) {
      if (!force) {
        return std::unexpected(dir.string() +
                               ": directory exists and is not empty (use --force to overwrite)");
      }
      std::vector<fs::path> old;
      for (const auto& entry : fs::recursive_directory_iterator(dir, ec)) {
        if (entry.is_regular_file() && IsOldSessionFile(dir, entry.path()))
          old.push_back(entry.path());
      }
      for (const fs::path& path : old) {
        if (!fs::remove(path, ec))
          return std::unexpected(path.string() + ": cannot remove: " + ec.message());
      }
    }
  }
  fs::create_directories(dir / "runs", ec);
  if (ec) return std::unexpected((dir / "runs").string() + ": cannot create: " + ec.message());
  return {};
}

}  // namespace

session::Session MakeSimSession(const SimSpec& spec, const std::vector<estimator::RunData>& runs,
                                const SimProvenance& provenance) {
  session::Session session;
  session.serial = spec.serial;
  // One rate for the session: the first run's (bench sessions have one; per-run rates of a spec
  // that mixes them are in "simulation").
  session.sample_rate_hz = spec.runs.empty() ? 0.0 : spec.runs.front().sample_rate_hz;

  nlohmann::json plans = nlohmann::json::array();
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const int id = static_cast<int>(i) + 1;
    session.runs.push_back({id, RunFileName(id), runs[i].omega_rad_s, "complete"});
    const estimator::RunPlan& plan = spec.runs.at(i);
    plans.push_back({{"id", id},
                     {"a", plan.a},
                     {"b", plan.b},
                     {"theta_rad", plan.theta_rad},
                     {"phi_rad", plan.phi_rad},
                     {"omega_rad_s", plan.omega_rad_s},
                     {"sample_rate_hz", plan.sample_rate_hz},
                     {"duration_s", plan.duration_s},
                     {"samples", runs[i].size()}});
  }

  nlohmann::json& doc = session.document;
  doc = nlohmann::json::object();
  doc["software_version"] = provenance.software_version;
  doc["spec_file"] = spec.file.filename().string();
  doc["spec_sha256"] = provenance.spec_sha256;
  if (!spec.description.empty()) doc["description"] = spec.description;
  doc["simulation"] = {{"delta", ToJson(spec.delta)}, {"xi", ToJson(spec.xi)},
                       {"sigma", spec.sigma},         {"seed", spec.seed},
                       {"generator", kSimGenerator},  {"runs", plans}};
  return session;
}

std::expected<void, std::string> WriteSimSession(const fs::path& dir,
                                                 const session::Session& session,
                                                 const std::vector<estimator::RunData>& runs,
                                                 bool force) {
  if (auto prepared = PrepareDirectory(dir, force); !prepared) return prepared;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    session::RunSamples samples;
    samples.t_s = runs[i].t_s;
    samples.y = runs[i].y;
    auto written = session::WriteRunCsv(dir / session.runs.at(i).file, samples);
    if (!written) return std::unexpected(written.error().ToString());
  }
  auto written = session::WriteSessionJson(dir, session);
  if (!written) return std::unexpected(written.error().ToString());
  return {};
}

}  // namespace hrgbench::app
