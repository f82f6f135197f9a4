// io::Hdf5Reader reads back what io::Hdf5Writer writes (the one HDF5 layout), and names
// the file in every error.

#include "deploysim/io/hdf5_reader.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/io/hdf5_writer.h"
#include "temp_dir_test.h"

namespace deploysim::io {
namespace {

class Hdf5ReaderTest : public testing::TempDirTest {};

TEST_F(Hdf5ReaderTest, ReadsBackWhatTheWriterWrote) {
  const std::string path = Path("t.h5");
  {
    Hdf5Writer w(path);
    w.Doubles("/g/x", {2, 2}, {1.0, 0.1, -2.5e-300, 1e300}, "m", "a matrix");
    w.Integers("/g/n", {-3, 9007199254740993LL}, "1", "integers");
    w.Strings("/s", {"alpha", "", "gamma"}, "text");
    w.Attribute("/", "kind", "test file");
    w.Attribute("/g", "note", "a group attribute");
    w.Commit();
  }
  const Hdf5Reader r(path);
  EXPECT_EQ(r.path(), path);
  EXPECT_TRUE(r.Exists("/g/x"));
  EXPECT_TRUE(r.Exists("g"));
  EXPECT_FALSE(r.Exists("/g/y"));
  EXPECT_FALSE(r.Exists("/missing/y"));
  EXPECT_EQ(r.KindOf("/g/x"), Hdf5Reader::Kind::kFloat);
  EXPECT_EQ(r.KindOf("/g/n"), Hdf5Reader::Kind::kInteger);
  EXPECT_EQ(r.KindOf("/s"), Hdf5Reader::Kind::kText);
  EXPECT_EQ(r.Numbers("/g/x"), (std::vector<double>{1.0, 0.1, -2.5e-300, 1e300}));
  EXPECT_EQ(r.Numbers("/g/n"), (std::vector<double>{-3.0, 9007199254740992.0}));
  EXPECT_EQ(r.Strings("/s"), (std::vector<std::string>{"alpha", "", "gamma"}));
  EXPECT_EQ(r.Attributes("/").at("kind"), "test file");
  EXPECT_EQ(r.Attribute("/g", "note"), "a group attribute");
  EXPECT_EQ(r.Attribute("/g/x", "units"), "m");
  EXPECT_EQ(r.Attributes("/s").at("description"), "text");
}

TEST_F(Hdf5ReaderTest, ErrorsNameTheFile) {
  const std::string path = Path("t.h5");
  {
    Hdf5Writer w(path);
    w.Strings("/s", {"a"}, "text");
    w.Commit();
  }
  const Hdf5Reader r(path);
  auto expect_error = [&path](const auto& f, const std::string& what) {
    try {
      f();
      FAIL() << "no error for " << what;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_error([&] { (void)r.Numbers("/s"); }, "expected numbers");
  expect_error([&] { (void)r.Attribute("/s", "units2"); }, "no attribute units2");
  expect_error([&] { (void)r.Strings("/nothing"); }, "HDF5 error");
  const std::string missing = Path("missing.h5");
  EXPECT_THROW(Hdf5Reader{missing}, std::runtime_error);
  const std::string text = Write("not.h5", "plain text\n");
  try {
    Hdf5Reader bad(text);
    FAIL() << "read a text file as HDF5";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), text + ": not an HDF5 file");
  }
}

}  // namespace
}  // namespace deploysim::io
