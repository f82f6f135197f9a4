#pragma once

/// Every numeric value of a YAML file, and the file with one of them replaced: for the
/// tests that give each numeric key of a profile, model or sweep an extreme value (the
/// overflow tests of the io and sweep modules).

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <variant>
#include <vector>

namespace deploysim::testing {

/// The way from the document's root to a node: map keys and sequence indices.
using KeyPath = std::vector<std::variant<std::string, std::size_t>>;

inline std::string ToString(const KeyPath& path) {
  std::string s;
  for (const auto& step : path) {
    if (const auto* key = std::get_if<std::string>(&step)) {
      s += (s.empty() ? "" : ".") + *key;
    } else {
      s += "[" + std::to_string(std::get<std::size_t>(step)) + "]";
    }
  }
  return s;
}

/// True when the whole scalar reads as a number ("60", "-2.5e-3"; not "yes" or "a1").
inline bool IsNumber(const std::string& text) {
  if (text.empty()) return false;
  char* end = nullptr;
  std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

namespace detail {
inline void CollectNumbers(const YAML::Node& node, KeyPath& path, std::vector<KeyPath>& out) {
  if (node.IsScalar()) {
    if (IsNumber(node.Scalar())) out.push_back(path);
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) {
      path.emplace_back(i);
      CollectNumbers(node[i], path, out);
      path.pop_back();
    }
  } else if (node.IsMap()) {
    for (const auto& kv : node) {
      path.emplace_back(kv.first.Scalar());
      CollectNumbers(kv.second, path, out);
      path.pop_back();
    }
  }
}
}  // namespace detail

/// The paths of every numeric scalar of `text`, in document order.
inline std::vector<KeyPath> NumericKeys(const std::string& text) {
  std::vector<KeyPath> out;
  KeyPath path;
  detail::CollectNumbers(YAML::Load(text), path, out);
  return out;
}

/// `text` with the scalar at `path` replaced by `value` (written as given: "1e308").
inline std::string WithValue(const std::string& text,
                             const KeyPath& path,
                             const std::string& value) {
  YAML::Node root = YAML::Clone(YAML::Load(text));
  YAML::Node node = root;
  for (const auto& step : path) {
    if (const auto* key = std::get_if<std::string>(&step)) {
      node.reset(node[*key]);
    } else {
      node.reset(node[std::get<std::size_t>(step)]);
    }
  }
  node = value;
  YAML::Emitter out;
  out << root;
  return out.c_str();
}

/// Gives every numeric key of the file at `path` the values 1e308, -1e308, 1e154 and
/// -1e154 in turn and asks `outcome` ("" when accepted, else the refusal) each time: a
/// refusal must be one line. Checks first that the file as it is is accepted; restores it
/// at the end. Returns how many values were accepted (DEPLOYSIM_SHOW_ACCEPTED lists them).
inline int GiveEveryKeyExtremes(const std::string& path,
                                const std::function<std::string()>& outcome) {
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(outcome(), "") << path << " as shipped";
  int accepted = 0;
  for (const KeyPath& key : NumericKeys(text)) {
    for (const char* value : {"1e308", "-1e308", "1e154", "-1e154"}) {
      std::ofstream(path) << WithValue(text, key, value);
      const std::string what = outcome();
      SCOPED_TRACE(path + ": " + ToString(key) + " = " + value);
      if (what.empty()) {
        if (std::getenv("DEPLOYSIM_SHOW_ACCEPTED") != nullptr) {  // to review them
          std::printf("accepted %s: %s = %s\n", path.c_str(), ToString(key).c_str(), value);
        }
        ++accepted;
      } else {
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;  // one line
      }
    }
  }
  std::ofstream(path) << text;
  return accepted;
}

}  // namespace deploysim::testing
