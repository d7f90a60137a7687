// hrg_gyro_v2.dbc is the vendor document; gyro_protocol.hpp / GyroCodec are the implementation.
// A tiny DBC reader (just the BO_, SG_, BA_ and VAL_ lines this file uses) checks that the two
// agree: ids (node 0's, and the node-id mask), lengths, frame kinds, the version attribute,
// enumerations, and that every signal, decoded generically from codec-encoded frames with the DBC's
// start bit, length, byte order, signedness and factor, gives back the value the codec was given.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "gyro_can/gyro_codec.hpp"

namespace hrgbench::drivers::gyro_can {
namespace {

struct DbcSignal {
  std::string name;
  int start = 0;
  int length = 0;
  bool little_endian = true;
  bool is_signed = false;
  double factor = 1.0;
  double offset = 0.0;
  std::string unit;
};

struct DbcMessage {
  std::uint32_t id = 0;
  std::string name;
  int length = 0;
  std::vector<DbcSignal> signals;
  const DbcSignal* Find(const std::string& name_) const {
    for (const DbcSignal& s : signals) {
      if (s.name == name_) return &s;
    }
    return nullptr;
  }
};

struct Dbc {
  std::map<std::uint32_t, DbcMessage> messages;
  std::map<std::string, std::string> attributes;  // global BA_
  std::map<std::pair<std::uint32_t, std::string>, std::string> message_attributes;
  std::map<std::pair<std::uint32_t, std::string>, std::map<long, std::string>> value_tables;
};

Dbc ReadDbc(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  Dbc dbc;
  const std::regex bo(R"re(^BO_ (\d+) (\w+): (\d+) (\w+)\s*$)re");
  const std::regex sg(
      R"re(^ SG_ (\w+) : (\d+)\|(\d+)@([01])([+-]) \(([-\d.eE+]+),([-\d.eE+]+)\) \[[^\]]*\] "([^"]*)" [\w,]+\s*$)re");
  const std::regex ba_global(R"re(^BA_ "(\w+)" "?([^";]*)"?;\s*$)re");
  const std::regex ba_message(R"re(^BA_ "(\w+)" BO_ (\d+) "?([^";]*)"?;\s*$)re");
  const std::regex val(R"re(^VAL_ (\d+) (\w+) (.*);\s*$)re");
  const std::regex val_entry(R"re((-?\d+) "([^"]*)")re");
  std::string line;
  DbcMessage* current = nullptr;
  std::smatch m;
  while (std::getline(in, line)) {
    if (std::regex_match(line, m, bo)) {
      const auto id = static_cast<std::uint32_t>(std::stoul(m[1]));
      current = &dbc.messages[id];
      current->id = id;
      current->name = m[2];
      current->length = std::stoi(m[3]);
    } else if (std::regex_match(line, m, sg)) {
      EXPECT_NE(current, nullptr) << line;
      if (current == nullptr) continue;
      current->signals.push_back({m[1], std::stoi(m[2]), std::stoi(m[3]), m[4] == "1", m[5] == "-",
                                  std::stod(m[6]), std::stod(m[7]), m[8]});
    } else if (std::regex_match(line, m, ba_message)) {
      dbc.message_attributes[{static_cast<std::uint32_t>(std::stoul(m[2])), m[1]}] = m[3];
    } else if (std::regex_match(line, m, ba_global)) {
      dbc.attributes[m[1]] = m[2];
    } else if (std::regex_match(line, m, val)) {
      auto& table = dbc.value_tables[{static_cast<std::uint32_t>(std::stoul(m[1])), m[2]}];
      const std::string entries = m[3];
      for (std::sregex_iterator it(entries.begin(), entries.end(), val_entry), end; it != end;
           ++it) {
        table[std::stol((*it)[1])] = (*it)[2];
      }
    } else if (line.rfind(" SG_", 0) == 0 || line.rfind("BO_ ", 0) == 0) {
      ADD_FAILURE() << "unparsed DBC line: " << line;
    }
  }
  return dbc;
}

const Dbc& TheDbc() {
  static const Dbc dbc = ReadDbc(HRGBENCH_SOURCE_DIR "/drivers/gyro_can/hrg_gyro_v2.dbc");
  return dbc;
}

// Generic little-endian (Intel) signal extraction, as any DBC tool does it.
double Physical(const DbcSignal& signal, const hw::CanFrame& frame) {
  std::uint64_t raw = 0;
  for (int i = 0; i < signal.length; ++i) {
    const int bit = signal.start + i;
    raw |= static_cast<std::uint64_t>((frame.data[static_cast<std::size_t>(bit / 8)] >> (bit % 8)) &
                                      1u)
           << i;
  }
  double value = static_cast<double>(raw);
  if (signal.is_signed && (raw >> (signal.length - 1)) != 0) {
    value -= std::ldexp(1.0, signal.length);
  }
  return value * signal.factor + signal.offset;
}

// The frames below are node 7's: the DBC's message is the one at the identifier without its node.
constexpr NodeId kNode = 7;

double Signal(std::uint32_t id, const char* name, const hw::CanFrame& frame) {
  EXPECT_EQ(frame.id, id | kNode) << name;
  const auto it = TheDbc().messages.find(MessageOf(frame.id));
  if (it == TheDbc().messages.end()) {
    ADD_FAILURE() << "no message " << id;
    return std::nan("");
  }
  const DbcSignal* signal = it->second.Find(name);
  if (signal == nullptr) {
    ADD_FAILURE() << "no signal " << name << " in " << it->second.name;
    return std::nan("");
  }
  return Physical(*signal, frame);
}

TEST(DbcConsistencyTest, MessagesMatchTheProtocolConstants) {
  const std::map<std::uint32_t, int> expected = {
      {can_id::kConfigure, length::kConfigure},
      {can_id::kExcite, length::kExcite},
      {can_id::kRelease, length::kSimpleCommand},
      {can_id::kStop, length::kSimpleCommand},
      {can_id::kStatusRequest, length::kSimpleCommand},
      {can_id::kParameter, length::kParameter},
      {can_id::kAck, length::kAck},
      {can_id::kStatus, length::kStatus},
      {can_id::kSampleA, length::kSample},
      {can_id::kSampleB, length::kSample},
      {can_id::kSampleFd, length::kSampleFd},
      {can_id::kReferencePhase, length::kReferencePhase},
      {can_id::kOperatingSample, length::kOperatingSample},
      {can_id::kOperatingLoopsA, length::kOperatingLoops},
      {can_id::kOperatingLoopsB, length::kOperatingLoops}};
  ASSERT_EQ(TheDbc().messages.size(), expected.size());
  for (const auto& [id, len] : expected) {
    const auto it = TheDbc().messages.find(id);
    ASSERT_NE(it, TheDbc().messages.end()) << "id " << id;
    EXPECT_EQ(it->second.length, len) << it->second.name;
    // Every message ends with the CRC byte, signals tile the payload without overlap.
    const DbcSignal* crc = it->second.Find("Crc");
    ASSERT_NE(crc, nullptr) << it->second.name;
    EXPECT_EQ(crc->start, 8 * (len - 1));
    EXPECT_EQ(crc->length, 8);
    std::vector<int> owner(static_cast<std::size_t>(8 * len), 0);
    for (const DbcSignal& s : it->second.signals) {
      EXPECT_TRUE(s.little_endian) << s.name;
      for (int b = s.start; b < s.start + s.length; ++b) {
        ASSERT_LT(b, 8 * len) << s.name;
        ++owner[static_cast<std::size_t>(b)];
      }
    }
    for (int b = 0; b < 8 * len; ++b) {
      // The FD frame's payload is all signals; classic frames too (reserved bits are signals).
      EXPECT_EQ(owner[static_cast<std::size_t>(b)], 1) << it->second.name << " bit " << b;
    }
  }
  EXPECT_EQ(TheDbc().message_attributes.at({can_id::kSampleFd, "VFrameFormat"}), "14");
  // The loops' report: every kOperatingLoopsInterval-th sample (ms at 1 kHz, as the samples' 1).
  EXPECT_EQ(TheDbc().message_attributes.at({can_id::kOperatingSample, "GenMsgCycleTime"}), "1");
  for (const std::uint32_t id : {can_id::kOperatingLoopsA, can_id::kOperatingLoopsB}) {
    EXPECT_EQ(TheDbc().message_attributes.at({id, "GenMsgCycleTime"}),
              std::to_string(kOperatingLoopsInterval));
  }
}

TEST(DbcConsistencyTest, VersionAndEnumerations) {
  EXPECT_EQ(TheDbc().attributes.at("ProtocolVersion"), std::to_string(kProtocolVersion));
  EXPECT_EQ(TheDbc().attributes.at("NodeIdMask"), std::to_string(kNodeIdMask));
  for (std::uint32_t id : {can_id::kAck, can_id::kStatus}) {
    const auto& modes = TheDbc().value_tables.at({id, "Mode"});
    ASSERT_EQ(modes.size(), 8u);
    for (const auto& [value, name] : modes) {
      // "FreeRun" vs ToString "free-run": compare letters only, case-insensitively.
      std::string a, b;
      for (char c : name) a += static_cast<char>(std::tolower(c));
      for (char c : hw::ToString(static_cast<hw::GyroMode>(value))) {
        if (c != '-') b += c;
      }
      EXPECT_EQ(a, b);
    }
  }
  const auto& results = TheDbc().value_tables.at({can_id::kAck, "Result"});
  EXPECT_EQ(results.size(), static_cast<std::size_t>(AckResult::kFaulted) + 1);
  const auto& commands = TheDbc().value_tables.at({can_id::kAck, "Command"});
  EXPECT_EQ(commands.begin()->first, static_cast<long>(Command::kConfigure));
  EXPECT_EQ(commands.rbegin()->first, static_cast<long>(Command::kParameter));
  const auto& ops = TheDbc().value_tables.at({can_id::kParameter, "Op"});
  EXPECT_EQ(ops.begin()->first, static_cast<long>(ParameterOp::kBegin));
  EXPECT_EQ(ops.rbegin()->first, static_cast<long>(ParameterOp::kRestore));
  EXPECT_EQ(ops.size(), 6u);
}

TEST(DbcConsistencyTest, SignalsDecodeToWhatTheCodecEncoded) {
  const hw::CanFrame configure = EncodeConfigure(
      kNode,
      {.token = 9, .sample_rate_hz = 1234, .format = FrameFormat::kFd, .status_rate_hz = 20});
  EXPECT_EQ(Signal(can_id::kConfigure, "Token", configure), 9);
  EXPECT_EQ(Signal(can_id::kConfigure, "SampleRate", configure), 1234);
  EXPECT_EQ(Signal(can_id::kConfigure, "FrameFormat", configure), 1);
  EXPECT_EQ(Signal(can_id::kConfigure, "StatusRate", configure), 20);

  const hw::CanFrame excite =
      EncodeExcite(kNode, {.token = 3, .a_raw = 12345, .b_raw = -4000, .theta_raw = -31416});
  EXPECT_DOUBLE_EQ(Signal(can_id::kExcite, "Amplitude", excite), 1.2345);
  EXPECT_DOUBLE_EQ(Signal(can_id::kExcite, "Quadrature", excite), -0.4);
  EXPECT_DOUBLE_EQ(Signal(can_id::kExcite, "WaveAngle", excite), -3.1416);

  const hw::CanFrame ack = EncodeAck(
      kNode, {Command::kRelease, 77, AckResult::kBadArgument, hw::GyroMode::kReady, 123456});
  EXPECT_EQ(Signal(can_id::kAck, "Command", ack), 0x42);
  EXPECT_EQ(Signal(can_id::kAck, "Token", ack), 77);
  EXPECT_EQ(Signal(can_id::kAck, "Result", ack), 2);
  EXPECT_EQ(Signal(can_id::kAck, "Mode", ack), 3);
  EXPECT_EQ(Signal(can_id::kAck, "Arg", ack), 123456);
  EXPECT_EQ(Signal(can_id::kAck, "Crc", ack), ack.data[7]);

  const hw::CanFrame operating = EncodeOperatingSample(
      kNode, {.seq = 7, .angle_output_raw = -2097152 * 3, .wave_angle_raw = 32768});
  EXPECT_EQ(Signal(can_id::kOperatingSample, "Seq", operating), 7);
  EXPECT_DOUBLE_EQ(Signal(can_id::kOperatingSample, "AngleOutput", operating), -3.0);
  EXPECT_NEAR(Signal(can_id::kOperatingSample, "WaveAngle", operating), std::numbers::pi / 2,
              1e-12);
  const hw::CanFrame loops_a = EncodeOperatingLoopsHalf(
      kNode, {.half = 0,
              .seq = 7,
              .value_raw = {QuantiseLoopValue(-4e-4, kEnergyErrorLsb),
                            QuantiseLoopValue(2.5e-8, kQuadratureRatioLsb)}});
  EXPECT_EQ(Signal(can_id::kOperatingLoopsA, "Seq", loops_a), 7);
  EXPECT_NEAR(Signal(can_id::kOperatingLoopsA, "EnergyError", loops_a), -4e-4, kEnergyErrorLsb / 2);
  EXPECT_NEAR(Signal(can_id::kOperatingLoopsA, "QuadratureRatio", loops_a), 2.5e-8,
              kQuadratureRatioLsb / 2);
  const hw::CanFrame loops_b =
      EncodeOperatingLoopsHalf(kNode, {.half = 1,
                                       .seq = 7,
                                       .value_raw = {QuantiseLoopValue(1.2e-3, kLoopEffortLsb),
                                                     QuantiseLoopValue(-3e-4, kLoopEffortLsb)}});
  EXPECT_EQ(Signal(can_id::kOperatingLoopsB, "Seq", loops_b), 7);
  EXPECT_NEAR(Signal(can_id::kOperatingLoopsB, "AmplitudeEffort", loops_b), 1.2e-3,
              kLoopEffortLsb / 2);
  EXPECT_NEAR(Signal(can_id::kOperatingLoopsB, "QuadratureEffort", loops_b), -3e-4,
              kLoopEffortLsb / 2);
  EXPECT_EQ(Signal(can_id::kOperatingLoopsB, "Crc", loops_b), loops_b.data[7]);
  const hw::CanFrame whole_angle = EncodeConfigure(
      kNode, {.token = 1, .sample_rate_hz = 1000, .run_mode = RunMode::kWholeAngle});
  EXPECT_EQ(Signal(can_id::kConfigure, "RunMode", whole_angle), 1);
  EXPECT_EQ(Signal(can_id::kConfigure, "Reserved", whole_angle), 0);

  const hw::CanFrame parameter =
      EncodeParameter(kNode, {.token = 5, .op = ParameterOp::kWrite, .index = 46, .value = 0xC9FF});
  EXPECT_EQ(Signal(can_id::kParameter, "Token", parameter), 5);
  EXPECT_EQ(Signal(can_id::kParameter, "Op", parameter), 2);
  EXPECT_EQ(Signal(can_id::kParameter, "WordIndex", parameter), 46);
  EXPECT_EQ(Signal(can_id::kParameter, "Value", parameter), 0xC9FF);
  EXPECT_EQ(Signal(can_id::kParameter, "Reserved", parameter), 0);

  const hw::CanFrame status =
      EncodeStatus(kNode, {.mode = hw::GyroMode::kFreeRun,
                           .pll_lock = true,
                           .ready = false,
                           .fault_bits = hw::gyro_fault::kSampleOverrun | hw::gyro_fault::kInternal,
                           .frequency_mhz = 5123456,
                           .temperature_centi_c = -1234});
  EXPECT_EQ(Signal(can_id::kStatus, "Mode", status), 4);
  EXPECT_EQ(Signal(can_id::kStatus, "PllLock", status), 1);
  EXPECT_EQ(Signal(can_id::kStatus, "Ready", status), 0);
  EXPECT_EQ(Signal(can_id::kStatus, "FaultSampleOverrun", status), 1);
  EXPECT_EQ(Signal(can_id::kStatus, "FaultInternal", status), 1);
  EXPECT_EQ(Signal(can_id::kStatus, "FaultPllUnlock", status), 0);
  EXPECT_DOUBLE_EQ(Signal(can_id::kStatus, "ResonantFrequency", status), 5123.456);
  EXPECT_DOUBLE_EQ(Signal(can_id::kStatus, "Temperature", status), -12.34);

  const hw::CanFrame sample_b =
      EncodeSampleHalf(kNode, {.half = 1, .seq = 250, .y_raw = {QuantiseY(0.7), QuantiseY(-1.3)}});
  EXPECT_EQ(Signal(can_id::kSampleB, "Seq", sample_b), 250);
  EXPECT_EQ(Signal(can_id::kSampleB, "Y3", sample_b), DequantiseY(QuantiseY(0.7)));
  EXPECT_EQ(Signal(can_id::kSampleB, "Y4", sample_b), DequantiseY(QuantiseY(-1.3)));

  const hw::CanFrame reference =
      EncodeReferencePhase(kNode, {.seq = 54321, .phase_raw = QuantiseReferencePhase(-2.5)});
  EXPECT_EQ(Signal(can_id::kReferencePhase, "Seq", reference), 54321);
  EXPECT_DOUBLE_EQ(Signal(can_id::kReferencePhase, "Phase", reference),
                   DequantiseReferencePhase(QuantiseReferencePhase(-2.5)));
  EXPECT_NEAR(Signal(can_id::kReferencePhase, "Phase", reference), 2 * std::numbers::pi - 2.5,
              1e-9);
  EXPECT_EQ(Signal(can_id::kReferencePhase, "Reserved", reference), 0);

  SampleFdBlock block{.seq = 40000, .count = 5, .y_raw = {}};
  for (std::size_t s = 0; s < 5; ++s) {
    for (std::size_t c = 0; c < 4; ++c) {
      block.y_raw[s][c] = QuantiseY(0.1 * static_cast<double>(s) - 0.37 * static_cast<double>(c));
    }
  }
  const hw::CanFrame fd = EncodeSampleFd(kNode, block);
  EXPECT_EQ(Signal(can_id::kSampleFd, "Seq", fd), 40000);
  EXPECT_EQ(Signal(can_id::kSampleFd, "Count", fd), 5);
  for (std::size_t s = 0; s < 5; ++s) {
    for (std::size_t c = 0; c < 4; ++c) {
      const std::string name = "S" + std::to_string(s) + "_Y" + std::to_string(c + 1);
      EXPECT_EQ(Signal(can_id::kSampleFd, name.c_str(), fd), DequantiseY(block.y_raw[s][c]))
          << name;
    }
  }
}

}  // namespace
}  // namespace hrgbench::drivers::gyro_can
