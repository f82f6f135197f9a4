#pragma once

/// Strict reading of YAML documents (internal to io; yaml-cpp stays inside this module).
/// Every rejection is ONE line (docs/file_formats.md):
///
///     <file>: <key.path[index]> = <value as written>: <rule>
///
/// Key paths join mapping keys with '.' and sequence indices as [i] (0-based), e.g.
/// `stages[2].until`, `configurations.closed.hinge_angles_deg[1]`. Values are shown as
/// written in the file (scalars verbatim, sequences and mappings in flow style,
/// shortened past 80 characters).
///
/// Strictness: keys are plain scalars, unique within their mapping and from the allowed
/// list; numbers are plain (unquoted) finite scalars; vectors are sequences of the
/// exact length.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "deploysim/io/number_format.h"
#include "deploysim/math/types.h"

namespace deploysim::io::internal {

/// The whole file as text. Throws std::runtime_error "<path>: cannot read: <reason>".
std::string ReadTextFile(const std::string& path);

/// A node as written, for messages (flow style, at most ~80 characters).
std::string Render(const YAML::Node& node);

/// One parsed YAML file: the document and the file name that every message starts with.
class YamlDocument {
 public:
  /// Parses `text` (read from `path`). Throws std::invalid_argument
  /// "<path>: line L, column C: YAML syntax error: <reason>" for syntax errors, and
  /// "<path>: ..." for an empty file, several documents or a top level that is not a
  /// mapping.
  YamlDocument(std::string path, std::string text);

  const std::string& path() const { return path_; }
  const std::string& text() const { return text_; }
  const YAML::Node& root() const { return root_; }

  /// Throws std::invalid_argument "<path>: <key> = <Render(value)>: <rule>".
  [[noreturn]] void Fail(const std::string& key,
                         const YAML::Node& value,
                         const std::string& rule) const;
  /// Throws std::invalid_argument "<path>: <key>: <rule>" (for a key that has no value,
  /// e.g. a missing one).
  [[noreturn]] void Fail(const std::string& key, const std::string& rule) const;

 private:
  std::string path_;
  std::string text_;
  YAML::Node root_;
};

/// `parent.key` (or `key` at the top level).
std::string JoinKey(const std::string& parent, const std::string& key);

/// The entries of a mapping in file order. Rejects a node that is not a mapping, keys
/// that are not plain scalars, and duplicate keys.
std::vector<std::pair<std::string, YAML::Node>> MappingEntries(const YamlDocument& doc,
                                                               const YAML::Node& node,
                                                               const std::string& path);

/// The elements of a sequence (rejects anything else).
std::vector<YAML::Node> SequenceElements(const YamlDocument& doc,
                                         const YAML::Node& node,
                                         const std::string& path,
                                         const std::string& what);

/// A finite number written as a plain scalar.
double ReadNumber(const YamlDocument& doc, const YAML::Node& node, const std::string& path);

/// A string (a scalar; plain, quoted or block).
std::string ReadText(const YamlDocument& doc, const YAML::Node& node, const std::string& path);

/// true / false (YAML 1.1 spellings as yaml-cpp reads them: yes/no, on/off too).
bool ReadBool(const YamlDocument& doc, const YAML::Node& node, const std::string& path);

/// A sequence of finite numbers; exactly `size` of them unless size < 0.
Eigen::VectorXd ReadNumbers(const YamlDocument& doc,
                            const YAML::Node& node,
                            const std::string& path,
                            int size);

/// A 3x3 matrix written as three rows [[a, b, c], [d, e, f], [g, h, i]].
math::Mat3 ReadMatrix3(const YamlDocument& doc, const YAML::Node& node, const std::string& path);

/// A mapping read strictly: every key must be in `allowed`.
class Fields {
 public:
  Fields(const YamlDocument& doc,
         const YAML::Node& node,
         std::string path,
         const std::vector<std::string>& allowed);

  const YamlDocument& doc() const { return *doc_; }
  const std::string& path() const { return path_; }
  const YAML::Node& node() const { return node_; }

  bool Has(const std::string& key) const;
  /// Key path of `key` in this mapping.
  std::string Key(const std::string& key) const { return JoinKey(path_, key); }
  /// The value of a required key (throws "<path>.<key>: required key is missing").
  const YAML::Node& Get(const std::string& key) const;

  double Number(const std::string& key) const;
  std::optional<double> OptionalNumber(const std::string& key) const;
  std::string Text(const std::string& key) const;
  std::optional<std::string> OptionalText(const std::string& key) const;
  std::optional<bool> OptionalBool(const std::string& key) const;
  /// Exactly `size` numbers.
  Eigen::VectorXd Numbers(const std::string& key, int size) const;
  math::Vec3 Vector3(const std::string& key) const;
  math::Mat3 Matrix3(const std::string& key) const;
  Fields Mapping(const std::string& key, const std::vector<std::string>& allowed) const;

  /// Throws "<path>.<key> = <value>: <rule>".
  [[noreturn]] void Fail(const std::string& key, const std::string& rule) const;
  /// Requires exactly one of `a`, `b` to be present.
  void RequireExactlyOne(const std::string& a, const std::string& b) const;

 private:
  const YAML::Node* Find(const std::string& key) const;

  const YamlDocument* doc_;
  YAML::Node node_;
  std::string path_;
  std::vector<std::pair<std::string, YAML::Node>> entries_;
};

}  // namespace deploysim::io::internal
