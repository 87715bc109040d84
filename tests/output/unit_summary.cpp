// summary.json writer: JSON text, number formatting, nesting, atomic write.
#include <fretsim/output/summary.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

using fretsim::output::Summary;

namespace
{
  std::filesystem::path scratch_directory(const std::string &name)
  {
    const auto directory = std::filesystem::path(FRETSIM_BINARY_DIR) / "test_output" / name;
    std::filesystem::remove_all(directory);
    std::filesystem::create_directories(directory);
    return directory;
  }

  std::string file_text(const std::filesystem::path &path)
  {
    std::ifstream      in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }
} // namespace

TEST(Summary, CompactTextKeepsOrderAndTypes)
{
  Summary s;
  s.set("scene", std::string("concentrated"));
  s.set("steps", 400LL);
  s.set("complete", true);
  s.set("ratio", 0.25);
  s.set("list", std::vector<double>{1.0, -2.5});
  s.set("empty", std::vector<double>{});
  EXPECT_EQ(s.to_json(),
            R"({"scene": "concentrated", "steps": 400, "complete": true, "ratio": 0.25, "list": [1, -2.5], "empty": []})");
}

TEST(Summary, SettingAKeyAgainReplacesItInPlace)
{
  Summary s;
  s.set("a", 1LL);
  s.set("b", 2LL);
  s.set("a", std::string("again"));
  EXPECT_EQ(s.to_json(), R"({"a": "again", "b": 2})");
}

TEST(Summary, StringsAreEscaped)
{
  Summary s;
  s.set("quote\"key", std::string("a\"b\\c\nd\te\r\b\f\x01 µm"));
  EXPECT_EQ(s.to_json(), "{\"quote\\\"key\": \"a\\\"b\\\\c\\nd\\te\\r\\b\\f\\u0001 µm\"}");
}

TEST(Summary, NonFiniteNumbersBecomeNull)
{
  Summary s;
  s.set("nan", std::numeric_limits<double>::quiet_NaN());
  s.set("inf", -std::numeric_limits<double>::infinity());
  s.set("list", std::vector<double>{1.0, std::numeric_limits<double>::quiet_NaN()});
  EXPECT_EQ(s.to_json(), R"({"nan": null, "inf": null, "list": [1, null]})");
}

TEST(Summary, DoublesRoundTripExactly)
{
  for (const double value : {0.1, 1.0 / 3.0, 2.0 / 3.0 * 1e-300, 6.02214076e23, -1.25e-6, 5e-324,
                             std::numeric_limits<double>::max(), 0.30000000000000004})
    {
      Summary s;
      s.set("v", value);
      const std::string json = s.to_json();
      const std::string text = json.substr(6, json.size() - 7); // {"v": ...}
      EXPECT_EQ(std::strtod(text.c_str(), nullptr), value) << json;
      EXPECT_LE(text.size(), 24u) << json;
    }
  Summary s;
  s.set("v", 0.1);
  EXPECT_EQ(s.to_json(), R"({"v": 0.1})"); // shortest text that round-trips
}

TEST(Summary, NestedObjectsCompactAndIndented)
{
  Summary times;
  times.set("normal_contact", 0.5);
  times.set("traction", 2.0);
  Summary none;
  Summary s;
  s.set("scene", std::string("x, {y}: \"z\""));
  s.set_object("stage_times_s", times);
  s.set_object("empty", none);
  s.set("list", std::vector<double>{1.0, 2.0});
  EXPECT_EQ(s.to_json(),
            R"({"scene": "x, {y}: \"z\"", "stage_times_s": {"normal_contact": 0.5, "traction": 2}, "empty": {}, "list": [1, 2]})");
  EXPECT_EQ(s.to_json(2), "{\n"
                          "  \"scene\": \"x, {y}: \\\"z\\\"\",\n"
                          "  \"stage_times_s\": {\n"
                          "    \"normal_contact\": 0.5,\n"
                          "    \"traction\": 2\n"
                          "  },\n"
                          "  \"empty\": {},\n"
                          "  \"list\": [1, 2]\n"
                          "}");
  EXPECT_EQ(Summary().to_json(2), "{}");
}

TEST(Summary, WriteIsAtomicAndLeavesNoTemporaryFile)
{
  const auto directory = scratch_directory("summary_write");
  const auto path      = directory / "summary.json";
  {
    std::ofstream old(path);
    old << "old content that must be replaced";
  }
  Summary s;
  s.set("scene", std::string("concentrated"));
  s.set("wall_time_s", 1.5);
  s.write(path.string());
  EXPECT_EQ(file_text(path), s.to_json(2) + "\n");
  EXPECT_FALSE(std::filesystem::exists(directory / "summary.json.tmp"));
  int files = 0;
  for ([[maybe_unused]] const auto &entry : std::filesystem::directory_iterator(directory))
    ++files;
  EXPECT_EQ(files, 1);
}

TEST(Summary, WriteFailureNamesThePath)
{
  const auto  directory = scratch_directory("summary_write_failure");
  const auto  path      = (directory / "missing_folder" / "summary.json").string();
  Summary     s;
  s.set("a", 1LL);
  try
    {
      s.write(path);
      FAIL() << "writing into a missing folder must throw";
    }
  catch (const std::runtime_error &error)
    {
      EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
    }
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}
