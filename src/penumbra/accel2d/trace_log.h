#pragma once
/// The traversal path of one ray in the lecture's notation: every node is written when it is
/// entered and again each time the walk returns to it, e.g. "l1 l2 l4 O3 l4 O5 l4 l2 l3 O2 l3 O1".
#include <string>
#include <vector>

namespace penumbra::lab2d {

/// Records the nodes a traversal enters; the returns are implied by the depths.
class TraceLog {
 public:
  /// Enters a node at `depth` (the root is 0): first writes the ancestors the walk returns to
  /// (those deeper than depth - 1, then the parent), then the node's label.
  void enter(size_t depth, const std::string& label) {
    if (depth > 0) return_to(depth - 1);
    if (depth == 0) path_.clear();
    path_.push_back(label);
    tokens_.push_back(label);
  }
  /// Returns from the current node up to its ancestor at `depth`, writing each node returned to.
  void return_to(size_t depth) {
    while (path_.size() > depth + 1) {
      path_.pop_back();
      tokens_.push_back(path_.back());
    }
  }
  /// Ends a walk that found nothing: it returns all the way to the root.
  void return_to_root() {
    while (path_.size() > 1) {
      path_.pop_back();
      tokens_.push_back(path_.back());
    }
  }
  /// The tokens written so far.
  const std::vector<std::string>& tokens() const { return tokens_; }
  /// The path as one line, tokens separated by spaces.
  std::string str() const {
    std::string s;
    for (const auto& t : tokens_) {
      if (!s.empty()) s += ' ';
      s += t;
    }
    return s;
  }

 private:
  std::vector<std::string> path_;
  std::vector<std::string> tokens_;
};

}  // namespace penumbra::lab2d
