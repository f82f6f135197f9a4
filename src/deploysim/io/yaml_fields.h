#pragma once

/// Strict reading of YAML documents, for the readers of deploysim's own file formats
/// (models and profiles in io, sweep files in sweep). yaml-cpp stays inside io: no
/// yaml-cpp type appears here (YamlNode is an opaque handle), so a reader outside io
/// neither includes nor links yaml-cpp. Library deploysim::io_yaml.
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

#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "deploysim/math/types.h"
#include "deploysim/math/units.h"

namespace deploysim::io::yaml {

/// One node of a parsed document (a scalar, sequence or mapping): an opaque handle,
/// cheap to copy; copies refer to the same node. Read it with the functions below.
class YamlNode {
 public:
  YamlNode();  ///< An undefined node.
  ~YamlNode();
  YamlNode(const YamlNode&);
  YamlNode& operator=(const YamlNode&);

  /// A scalar written without quotes (`12`, `rk4`; not `"12"`), or with an explicit
  /// numeric tag (`!!int 12`).
  bool IsPlainScalar() const;
  /// The text of a scalar as written (without quotes); empty for other nodes.
  std::string Scalar() const;

  struct Impl;  ///< Defined where yaml-cpp is included (yaml_fields.cc).
  const Impl& impl() const { return *impl_; }
  explicit YamlNode(std::shared_ptr<const Impl> impl);

 private:
  std::shared_ptr<const Impl> impl_;
};

/// Limits on input files (docs/file_formats.md). Every YAML file deploysim reads passes
/// them; past a limit the file is refused with one line naming the file and the limit.
/// The largest shipped file has a few KB; at the limits a file parses in ~0.2 s with a peak
/// RSS of ~60 MB (yaml-cpp keeps ~500 bytes per node: the node limit is what bounds memory).
/// Largest input file [bytes] (1 MiB). Only regular files are read (not devices, FIFOs,
/// directories), and never more than this + 1 bytes, even from a file that grows.
inline constexpr std::size_t kMaxFileBytes = std::size_t{1} << 20;
/// Most nodes (scalars, sequences, mappings) in a document, counted with every alias
/// expanded: bounds the memory of the parse and the work of anything that walks the tree
/// (a "billion laughs" of nested aliases is refused, not expanded).
inline constexpr std::size_t kMaxNodes = 100000;
/// Deepest nesting of sequences and mappings, aliases expanded (the deepest file format
/// needs 4: configurations.<name>.tensor[i][j]).
inline constexpr int kMaxDepth = 32;
/// Values echoed in messages are cut to this many bytes (ShortValue); file names to
/// kMaxShownPathBytes.
inline constexpr std::size_t kMaxShownBytes = 60;
inline constexpr std::size_t kMaxShownPathBytes = 160;
/// Longest name (of a model, profile, sweep, configuration, panel or stage) [bytes]: names
/// appear in messages, file attributes and CSV headers.
inline constexpr std::size_t kMaxNameBytes = 200;
/// Degrees in files (`..._deg`, `..._deg_s`) become radians (rad/s) on load by this factor
/// (nothing downstream sees degrees).
using math::kRadiansPerDegree;
/// Rates in revolutions per minute (`..._rpm`) become rad/s on load by this factor.
using math::kRadPerSecondPerRpm;

/// The whole file as bytes: a regular file of at most kMaxFileBytes bytes. Throws
/// std::runtime_error "<path>: cannot read: <reason>" (missing, unreadable, not a regular
/// file, larger than kMaxFileBytes). Never blocks on a FIFO and never reads a device; the
/// type is checked before opening and again on the open file. (The text is checked to be
/// UTF-8 by YamlDocument.)
std::string ReadTextFile(const std::string& path);

/// `value` for a message: at most kMaxShownBytes bytes (cut at a UTF-8 character boundary,
/// then "... (N bytes)"), newlines and other control characters shown as escapes.
std::string ShortValue(const std::string& value, std::size_t max_bytes = kMaxShownBytes);

/// Names for a message: "a, b, c", each as ShortValue, at most 10 of them, then
/// ", ... (N in all)".
std::string ShortList(const std::vector<std::string>& names);

/// "" if `name` may be a name (of a model, profile, sweep, configuration, panel or stage),
/// else the rule it breaks: 1 to kMaxNameBytes bytes, no control characters (tab, line
/// breaks).
std::string NameProblem(const std::string& name);

/// A node as written, for messages (flow style, at most ~80 characters; long scalars as
/// ShortValue). The work is bounded whatever the node (nested aliases included).
std::string Render(const YamlNode& node);

/// One parsed YAML file: the document and the file name that every message starts with.
class YamlDocument {
 public:
  /// Parses `text` (read from `path`; any text, e.g. a fuzzer's). Throws
  /// std::invalid_argument "<path>: line L, column C: YAML syntax error: <reason>" for
  /// syntax errors, "<path>: line L, byte B: ..." for text that is not UTF-8 (or holds
  /// control characters), "<path>: line L, column C: ..." past kMaxNodes / kMaxDepth, for a
  /// recursive alias or a string value that is not UTF-8 text (e.g. "\0" or "\uD800"), and
  /// "<path>: ..." for a text over kMaxFileBytes, an empty file, several documents or a top
  /// level that is not a mapping. Never loops (yaml-cpp 0.7's LoadAll does, on a ',').
  YamlDocument(std::string path, std::string text);
  /// The same for a text that is no file (e.g. a document built from Python dicts):
  /// `path` names it in messages, and the files it names (FilePath) are resolved
  /// relative to `base_dir` instead of path's folder.
  YamlDocument(std::string path, std::string text, std::string base_dir);

  const std::string& path() const { return path_; }
  /// The folder that relative file names in the document are resolved against: the
  /// folder of path() unless given.
  const std::string& base_dir() const { return base_dir_; }
  const std::string& text() const { return text_; }
  const YamlNode& root() const { return root_; }

  /// Throws std::invalid_argument "<path>: <key> = <Render(value)>: <rule>".
  [[noreturn]] void Fail(const std::string& key,
                         const YamlNode& value,
                         const std::string& rule) const;
  /// Throws std::invalid_argument "<path>: <key>: <rule>" (for a key that has no value,
  /// e.g. a missing one).
  [[noreturn]] void Fail(const std::string& key, const std::string& rule) const;

 private:
  std::string path_;
  std::string text_;
  std::string base_dir_;
  YamlNode root_;
};

/// `parent.key` (or `key` at the top level); a long key as ShortValue.
std::string JoinKey(const std::string& parent, const std::string& key);

/// The entries of a mapping in file order. Rejects a node that is not a mapping, keys
/// that are not plain scalars, and duplicate keys.
std::vector<std::pair<std::string, YamlNode>> MappingEntries(const YamlDocument& doc,
                                                             const YamlNode& node,
                                                             const std::string& path);

/// The elements of a sequence (rejects anything else).
std::vector<YamlNode> SequenceElements(const YamlDocument& doc,
                                       const YamlNode& node,
                                       const std::string& path,
                                       const std::string& what);

/// A finite number written as a plain scalar.
double ReadNumber(const YamlDocument& doc, const YamlNode& node, const std::string& path);

/// A string (a scalar; plain, quoted or block).
std::string ReadText(const YamlDocument& doc, const YamlNode& node, const std::string& path);

/// true / false (YAML 1.1 spellings as yaml-cpp reads them: yes/no, on/off too).
bool ReadBool(const YamlDocument& doc, const YamlNode& node, const std::string& path);

/// A sequence of finite numbers; exactly `size` of them unless size < 0.
Eigen::VectorXd ReadNumbers(const YamlDocument& doc,
                            const YamlNode& node,
                            const std::string& path,
                            int size);

/// A 3x3 matrix written as three rows [[a, b, c], [d, e, f], [g, h, i]].
math::Mat3 ReadMatrix3(const YamlDocument& doc, const YamlNode& node, const std::string& path);

/// A mapping read strictly: every key must be in `allowed`.
class Fields {
 public:
  Fields(const YamlDocument& doc,
         const YamlNode& node,
         std::string path,
         const std::vector<std::string>& allowed);

  const YamlDocument& doc() const { return *doc_; }
  const std::string& path() const { return path_; }
  const YamlNode& node() const { return node_; }

  bool Has(const std::string& key) const;
  /// Key path of `key` in this mapping.
  std::string Key(const std::string& key) const { return JoinKey(path_, key); }
  /// The value of a required key (throws "<path>.<key>: required key is missing").
  const YamlNode& Get(const std::string& key) const;

  double Number(const std::string& key) const;
  std::optional<double> OptionalNumber(const std::string& key) const;
  /// A number given in degrees (`..._deg`) or degrees per second (`..._deg_s`), returned
  /// in radians (rad/s): Number(key) * kRadiansPerDegree.
  double Degrees(const std::string& key) const;
  std::optional<double> OptionalDegrees(const std::string& key) const;
  std::string Text(const std::string& key) const;
  /// A name: a string that passes NameProblem.
  std::string Name(const std::string& key) const;
  std::optional<std::string> OptionalText(const std::string& key) const;
  std::optional<bool> OptionalBool(const std::string& key) const;
  /// Exactly `size` numbers.
  Eigen::VectorXd Numbers(const std::string& key, int size) const;
  math::Vec3 Vector3(const std::string& key) const;
  math::Mat3 Matrix3(const std::string& key) const;
  Fields Mapping(const std::string& key, const std::vector<std::string>& allowed) const;

  /// The file named by `key` (a path relative to the document's base_dir()), resolved and
  /// checked to be readable. Throws std::invalid_argument for an empty name and
  /// std::runtime_error "<file>: <key> = <value>: cannot read <resolved>: <reason>".
  std::string FilePath(const std::string& key) const;

  /// Throws "<path>.<key> = <value>: <rule>".
  [[noreturn]] void Fail(const std::string& key, const std::string& rule) const;
  /// Requires exactly one of `a`, `b` to be present.
  void RequireExactlyOne(const std::string& a, const std::string& b) const;
  /// Requires exactly one of `keys` to be present; returns it.
  std::string RequireExactlyOne(const std::vector<std::string>& keys) const;

 private:
  const YamlNode* Find(const std::string& key) const;

  const YamlDocument* doc_;
  YamlNode node_;
  std::string path_;
  std::vector<std::pair<std::string, YamlNode>> entries_;
};

}  // namespace deploysim::io::yaml
