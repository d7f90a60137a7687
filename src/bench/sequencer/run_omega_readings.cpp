// A run's Ω as the sequencer measures it: both measurements, and the station's choice.

#include "bench/sequencer/run_omega_readings.hpp"

namespace hrgbench::bench::internal {

RunOmegaReadings::RunOmegaReadings(OmegaSourceSetting setting, std::size_t expected_reads)
    : setting_(setting) {
  angle_.Reserve(expected_reads);
}

StepOutcome RunOmegaReadings::ReadAngle(hw::RateTable& table, int run_id) {
  if (!angle_reported_) return StepOutcome::Ok();
  auto angle = table.ReadAngle();
  if (angle) {
    angle_.Add(*angle);
    return StepOutcome::Ok();
  }
  if (angle.error().code == hw::RateTableErrorCode::kNotSupported) {
    angle_reported_ = false;
    no_angle_reason_ = angle.error().message;
    if (setting_ != OmegaSourceSetting::kAngle) return StepOutcome::Ok();
    return StepOutcome::Error("omega_source = \"angle\", but the rate table reports no angle: " +
                              no_angle_reason_);
  }
  return StepOutcome::Error("rate table angle during run " + std::to_string(run_id) + ": " +
                            angle.error().ToString());
}

StepOutcome RunOmegaReadings::Finish(int axis_sign, double earth_rate_rad_s,
                                     double measured_at_start_rad_s, RunEnd& end) const {
  OmegaEstimate by_rate = rate_.Result();
  OmegaEstimate by_angle = angle_.Result();
  by_rate.omega_rad_s *= axis_sign;
  by_angle.omega_rad_s *= axis_sign;
  end.omega_rate_rad_s = by_rate.omega_rad_s + earth_rate_rad_s;
  end.omega_rate_std_error_rad_s = by_rate.std_error_rad_s;
  end.omega_rate_readings = by_rate.readings;
  end.omega_angle_rad_s = by_angle.omega_rad_s + earth_rate_rad_s;
  end.omega_angle_std_error_rad_s = by_angle.std_error_rad_s;
  end.omega_angle_readings = by_angle.readings;
  if (setting_ != OmegaSourceSetting::kRate && by_angle.valid()) {
    end.omega_source = std::string(ToString(OmegaSource::kAngle));
    end.omega_rad_s = end.omega_angle_rad_s;
    end.omega_std_error_rad_s = by_angle.std_error_rad_s;
    end.omega_readings = by_angle.readings;
    return StepOutcome::Ok();
  }
  end.omega_source = std::string(ToString(OmegaSource::kRate));
  end.omega_rad_s =
      (by_rate.valid() ? by_rate.omega_rad_s : measured_at_start_rad_s) + earth_rate_rad_s;
  end.omega_std_error_rad_s = by_rate.std_error_rad_s;
  end.omega_readings = by_rate.readings;
  if (setting_ != OmegaSourceSetting::kAngle) return StepOutcome::Ok();
  return StepOutcome::Error("omega_source = \"angle\", but there is no Ω from the angle: " +
                            NoAngleReason());
}

std::string RunOmegaReadings::NoAngleReason() const {
  if (!no_angle_reason_.empty()) return no_angle_reason_;
  if (!angle_.problem().empty()) return angle_.problem();
  return std::to_string(angle_.valid_readings()) + " valid angle readings (" +
         std::to_string(angle_.invalid_readings()) + " invalid), at least 2 at 2 instants needed";
}

}  // namespace hrgbench::bench::internal
