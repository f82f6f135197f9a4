// io::Hdf5Reader reads back what io::Hdf5Writer writes (the one HDF5 layout), and names
// the file in every error.

#include "deploysim/io/hdf5_reader.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/io/hdf5_writer.h"
#include "temp_dir_test.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

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

TEST_F(Hdf5ReaderTest, GrowingDatasetsReadAsOne) {
  const std::string path = Path("g.h5");
  std::vector<double> all;
  {
    Hdf5Writer w(path);
    const std::size_t h = w.GrowingDoubles("/rows/v", {2, 3}, "m", "growing");
    const std::size_t e = w.GrowingDoubles("/empty", {3}, "s", "never appended");
    const std::size_t z = w.GrowingDoubles("/zero_width", {0}, "1", "no columns");
    // Blocks across chunk boundaries (kChunkRows rows per chunk).
    for (std::size_t rows : {std::size_t{1}, Hdf5Writer::kChunkRows, std::size_t{7}}) {
      std::vector<double> block;
      for (std::size_t i = 0; i < 6 * rows; ++i) block.push_back(static_cast<double>(all.size()));
      all.insert(all.end(), block.begin(), block.end());
      w.AppendRows(h, block, rows);
      w.AppendRows(z, {}, rows);
    }
    (void)e;
    EXPECT_THROW(w.AppendRows(h, {1.0, 2.0}, 1), std::invalid_argument);
    w.Commit();
  }
  const Hdf5Reader r(path);
  EXPECT_EQ(r.Numbers("/rows/v"), all);
  EXPECT_EQ(r.Attribute("/rows/v", "units"), "m");
  EXPECT_TRUE(r.Numbers("/empty").empty());
  EXPECT_TRUE(r.Numbers("/zero_width").empty());
}

TEST(ValidUtf8Test, ReplacesEachInvalidSequence) {
  const std::string fffd = "\xEF\xBF\xBD";
  EXPECT_EQ(ValidUtf8("plain"), "plain");
  EXPECT_EQ(ValidUtf8("\xC3\xA9t\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x9A\x80"),
            "\xC3\xA9t\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x9A\x80");
  EXPECT_EQ(ValidUtf8("a\xFF"
                      "b"),
            "a" + fffd + "b");
  EXPECT_EQ(ValidUtf8("\x80"), fffd);                                   // stray continuation byte
  EXPECT_EQ(ValidUtf8("\xC3"), fffd);                                   // truncated at the end
  EXPECT_EQ(ValidUtf8("\xE2\x82x"), fffd + "x");                        // truncated: one U+FFFD
  EXPECT_EQ(ValidUtf8("\xC0\xAF"), fffd + fffd);                        // overlong '/'
  EXPECT_EQ(ValidUtf8("\xED\xA0\x80"), fffd + fffd + fffd);             // a surrogate
  EXPECT_EQ(ValidUtf8("\xF4\x90\x80\x80"), fffd + fffd + fffd + fffd);  // > U+10FFFF
}

TEST_F(Hdf5ReaderTest, InvalidUtf8IsNeverWritten) {
  const std::string path = Path("u.h5");
  const std::string bad = "stage \xFF\xFE name \xC3";
  {
    Hdf5Writer w(path);
    w.Strings("/s", {bad, "ok"}, "text");
    w.Attribute("/", "profile_text", "name: \xE9t\xE9\n");
    w.Commit();
  }
  const Hdf5Reader r(path);
  EXPECT_EQ(r.Strings("/s"),
            (std::vector<std::string>{"stage \xEF\xBF\xBD\xEF\xBF\xBD name \xEF\xBF\xBD", "ok"}));
  EXPECT_EQ(r.Attribute("/", "profile_text"), "name: \xEF\xBF\xBDt\xEF\xBF\xBD\n");
  // h5py decodes the strings as UTF-8 (it failed on the invalid bytes before).
  if (std::system("/usr/bin/python3 -c 'import h5py' 2>/dev/null") == 0) {
    const std::string script =
        "/usr/bin/python3 -c \"import h5py, sys; f = h5py.File(sys.argv[1], 'r'); "
        "v = [x.decode('utf-8') for x in f['s'][:]]; a = f.attrs['profile_text']; "
        "sys.exit(0 if v[0] == 'stage \\ufffd\\ufffd name \\ufffd' and "
        "a == 'name: \\ufffdt\\ufffd\\n' else 1)\" '" +
        path + "'";
    EXPECT_EQ(std::system(script.c_str()), 0) << script;
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
