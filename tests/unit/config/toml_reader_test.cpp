// The strict TOML reader on its own (toml_reader.hpp): what every loader of the project relies on.
// Each test writes the file a user could write and checks the error a user would read: the file,
// the line, the dotted key, the value exactly as written and what was expected.

#include "hrgbench/config/toml_reader.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "hrgbench/config/config_bounds.hpp"

namespace hrgbench::config_file {
namespace {

// A parsed text and a reader of its root, kept together (the reader refers to both).
struct Parsed {
  TomlDocument document;
  Source source;
  TableReader root;

  explicit Parsed(TomlDocument doc)
      : document(std::move(doc)),
        source("station.toml", document.text),
        root(document.root, "", source) {}
};

Parsed Parse(std::string_view text) {
  auto doc = ParseTomlText(text, "station.toml");
  EXPECT_TRUE(doc.has_value()) << (doc ? "" : doc.error().ToString());
  return Parsed(std::move(*doc));
}

TEST(TomlReader, SyntaxErrorNamesFileAndLine) {
  auto doc = ParseTomlText("a = 1\nb = = 2\n", "station.toml");
  ASSERT_FALSE(doc.has_value());
  EXPECT_EQ(doc.error().file, "station.toml");
  EXPECT_EQ(doc.error().line, 2u);
}

TEST(TomlReader, UnknownKeyIsAnErrorListingWhatIsAllowed) {
  Parsed p = Parse("port = 502\n\n[table]\nspeed = 1\nsped = 2\n");
  ASSERT_TRUE(RequiredInteger(p.root, "port", 1, 65535).has_value());
  auto table = SubTable(p.root, "table", true);
  ASSERT_TRUE(table.has_value() && *table != nullptr);
  TableReader reader(**table, "table", p.source);
  ASSERT_TRUE(OptionalNumber(reader, "speed", kAnyFinite, 0.0).has_value());
  EXPECT_FALSE(p.root.Unknown("port, table").has_value());
  const auto unknown = reader.Unknown("speed");
  ASSERT_TRUE(unknown.has_value());
  EXPECT_EQ(unknown->key, "table.sped");
  EXPECT_EQ(unknown->line, 5u);
  EXPECT_EQ(unknown->value, "2");
  EXPECT_NE(unknown->message.find("allowed here: speed"), std::string::npos) << unknown->message;
}

TEST(TomlReader, MissingRequiredKeyIsReportedAtItsTable) {
  Parsed p = Parse("name = \"x\"\n\n[gyro]\nnode = 3\n");
  auto gyro = SubTable(p.root, "gyro", true);
  ASSERT_TRUE(gyro.has_value());
  TableReader reader(**gyro, "gyro", p.source);
  const auto missing = RequiredNumber(reader, "sample_rate_hz", kPositive);
  ASSERT_FALSE(missing.has_value());
  EXPECT_EQ(missing.error().key, "gyro.sample_rate_hz");
  EXPECT_EQ(missing.error().line, 3u);
  EXPECT_TRUE(missing.error().value.empty());
  EXPECT_NE(missing.error().message.find("missing"), std::string::npos);
}

TEST(TomlReader, IntegerIsANumberButANumberIsNotAnInteger) {
  Parsed p = Parse("sigma = 0\nport = 502.0\n");
  const auto sigma = RequiredNumber(p.root, "sigma", kNonNegative);
  ASSERT_TRUE(sigma.has_value());
  EXPECT_EQ(*sigma, 0.0);
  const auto port = RequiredInteger(p.root, "port", 1, 65535);
  ASSERT_FALSE(port.has_value());
  EXPECT_EQ(port.error().key, "port");
  EXPECT_EQ(port.error().line, 2u);
  EXPECT_EQ(port.error().value, "502.0");
}

TEST(TomlReader, OutOfRangeQuotesTheValueAsWritten) {
  Parsed p = Parse("cutoff_hz = -0.30\ncount = 70000\n");
  const auto cutoff = RequiredNumber(p.root, "cutoff_hz", kPositive);
  ASSERT_FALSE(cutoff.has_value());
  EXPECT_EQ(cutoff.error().value, "-0.30");  // not "-0.29999999999999999"
  EXPECT_NE(cutoff.error().message.find("> 0"), std::string::npos) << cutoff.error().message;
  const auto count = RequiredInteger(p.root, "count", 0, 65535);
  ASSERT_FALSE(count.has_value());
  EXPECT_EQ(count.error().value, "70000");
  EXPECT_EQ(count.error().ToString().rfind("station.toml:2: key 'count' = 70000", 0), 0u)
      << count.error().ToString();
}

TEST(TomlReader, AbsentOptionalKeysTakeTheirDefaultOrNothing) {
  Parsed p = Parse("a = 1\n");
  EXPECT_EQ(*OptionalNumber(p.root, "b", kAnyFinite, 2.5), 2.5);
  EXPECT_EQ(*OptionalInteger(p.root, "c", 0, 9, 7), 7);
  EXPECT_FALSE(MaybeNumber(p.root, "d", kAnyFinite)->has_value());
  EXPECT_FALSE(MaybeInteger(p.root, "e", 0, 9)->has_value());
  EXPECT_TRUE(*OptionalBool(p.root, "f", true));
  auto table = SubTable(p.root, "g", false);
  ASSERT_TRUE(table.has_value());
  EXPECT_EQ(*table, nullptr);
  EXPECT_FALSE(SubTable(p.root, "h", true).has_value());
}

TEST(TomlReader, WrongTypesAreErrors) {
  Parsed p = Parse("a = \"1\"\nb = 1\nc = [1, 2]\nd = 1.5\n");
  EXPECT_FALSE(RequiredNumber(p.root, "a", kAnyFinite).has_value());
  EXPECT_FALSE(OptionalBool(p.root, "b", false).has_value());
  EXPECT_FALSE(RequiredString(p.root, "c").has_value());
  EXPECT_FALSE(SubTable(p.root, "d", true).has_value());
}

TEST(TomlReader, StringsAreBoundedAndPrintable) {
  const std::string long_name(kMaxNameBytes + 1, 'x');
  Parsed p = Parse("ok = \"unit-7\"\nbell = \"a\\u0007b\"\nlong = \"" + long_name +
                   "\"\nempty = \"\"\nnote = \"line one\\nline two\"\n");
  EXPECT_EQ(*RequiredString(p.root, "ok"), "unit-7");
  EXPECT_FALSE(RequiredString(p.root, "bell").has_value());
  EXPECT_FALSE(RequiredString(p.root, "long").has_value());
  EXPECT_FALSE(RequiredString(p.root, "empty").has_value());
  EXPECT_TRUE(OptionalString(p.root, "empty", "d", false).has_value());
  // A description may hold a line feed; a name may not.
  EXPECT_TRUE(OptionalString(p.root, "note", "", false, StringKind::kDescription).has_value());
  EXPECT_FALSE(OptionalString(p.root, "note", "", false, StringKind::kName).has_value());
}

TEST(TomlReader, ChoiceNamesTheChoices) {
  Parsed p = Parse("kind = \"butterworth\"\nstage = \"middle\"\n");
  EXPECT_EQ(*Choice(p.root, "kind", {"none", "butterworth"}, 0), 1u);
  const auto stage = Choice(p.root, "stage", {"before_gain", "after_gain"}, -1);
  ASSERT_FALSE(stage.has_value());
  EXPECT_EQ(stage.error().value, "\"middle\"");
  EXPECT_NE(stage.error().message.find("before_gain"), std::string::npos) << stage.error().message;
  EXPECT_FALSE(Choice(p.root, "absent", {"a"}, -1).has_value());
  EXPECT_EQ(*Choice(p.root, "absent2", {"a", "b"}, 1), 1u);
}

TEST(TomlReader, VectorsCheckLengthAndEachElement) {
  Parsed p = Parse("xi = [0.0, 1e-3, 2e-3, 3e-3]\nshort = [1, 2]\nbad = [1, 2, -3, 4]\n");
  const auto xi = RequiredVector<4>(p.root, "xi", kAnyFinite);
  ASSERT_TRUE(xi.has_value());
  EXPECT_EQ((*xi)(3), 3e-3);
  const auto too_short = RequiredVector<4>(p.root, "short", kAnyFinite);
  ASSERT_FALSE(too_short.has_value());
  EXPECT_NE(too_short.error().message.find("wrong length 2"), std::string::npos);
  const auto bad = RequiredVector<4>(p.root, "bad", kNonNegative);
  ASSERT_FALSE(bad.has_value());
  EXPECT_EQ(bad.error().key, "bad[2]");
  EXPECT_EQ(bad.error().value, "-3");
}

TEST(TomlReader, ForbiddenKeyIsAnErrorWithTheReason) {
  Parsed p = Parse("device = \"/dev/ttyS0\"\n");
  const auto error = Forbid(p.root, "device", "only with transport = \"rtu\"");
  ASSERT_TRUE(error.has_value());
  EXPECT_NE(error->message.find("only with transport"), std::string::npos);
  EXPECT_FALSE(Forbid(p.root, "baud", "only with transport = \"rtu\"").has_value());
  EXPECT_FALSE(p.root.Unknown("device").has_value());
}

class TomlFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::temp_directory_path() /
        ("toml_reader_test." + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "." + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path Write(const std::string& name, const std::string& text) {
    const auto path = dir_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  std::filesystem::path dir_;
};

TEST_F(TomlFileTest, ReadsAFileAndFingerprintsItsBytes) {
  const auto path = Write("a.toml", "a = 1\n");
  auto doc = LoadTomlFile(path);
  ASSERT_TRUE(doc.has_value()) << doc.error().ToString();
  EXPECT_EQ(doc->text, "a = 1\n");
  // `printf 'a = 1\n' | sha256sum` (coreutils), not this project's SHA-256.
  EXPECT_EQ(doc->sha256_hex, "cb78bd8a17f7b751fe0d4663366dcbc257204033ef7ddd64b1f2969573b5b2e2");
  EXPECT_EQ(doc->root["a"].value<int64_t>(), 1);
}

TEST_F(TomlFileTest, RefusesWhatIsNotAReadableSmallRegularFile) {
  const auto missing = LoadTomlFile(dir_ / "none.toml");
  ASSERT_FALSE(missing.has_value());
  EXPECT_EQ(missing.error().line, 0u);
  EXPECT_EQ(missing.error().file, dir_ / "none.toml");
  EXPECT_FALSE(LoadTomlFile(dir_).has_value());
  const auto big = Write("big.toml", "# " + std::string(kMaxConfigFileBytes, 'x') + "\n");
  const auto too_big = LoadTomlFile(big);
  ASSERT_FALSE(too_big.has_value());
  EXPECT_EQ(too_big.error().line, 0u);
  EXPECT_FALSE(ParseTomlText(std::string(kMaxConfigFileBytes + 1, '#'), "x.toml").has_value());
}

}  // namespace
}  // namespace hrgbench::config_file
