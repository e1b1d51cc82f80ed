#include "shadow/shaft_hierarchy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/colour.h"

namespace penumbra::shadow {
namespace {

using scene::Aabb;

Aabb merged(const Aabb& a, const Aabb& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  return Aabb{glm::min(a.min, b.min), glm::max(a.max, b.max)};
}

double squaredDiagonal(const Aabb& b) {
  const glm::dvec3 d = b.size();
  return d.x * d.x + d.y * d.y + d.z * d.z;
}

// Which box alone reaches a face of the joint bounding box (Haines & Wallace 1994): a
// plane is needed only between a face reached by one box and a face reached by the other.
enum class Owner : uint8_t { kBoth, kA, kB };

Owner faceOwner(double a, double b, bool maxSide) {
  if (a == b) return Owner::kBoth;
  return (a < b) != maxSide ? Owner::kA : Owner::kB;
}

double corner(const Aabb& box, int axis, bool maxSide) {
  return maxSide ? box.max[axis] : box.min[axis];
}

[[noreturn]] void inputError(const std::string& what) {
  throw std::invalid_argument("ShaftHierarchy: " + what);
}

// Receiver vertex rows of the transfers, transposed to vertex-major order and keyed by a
// source's position in the KD-tree leaf order, with running luminance sums: the transfer
// from any source node (a contiguous range of that order) to a vertex is then two binary
// searches, and the §6 prune test costs O(vertices of the receiver node x log sources)
// whatever the number of sources. Build-time only.
class VertexTransferRows {
 public:
  VertexTransferRows(const RadianceTransfers& t, std::span<const uint32_t> sourcePosition) {
    const size_t vertexCount = t.receiverVertices.size();
    rowStart_.assign(vertexCount + 1, 0);
    for (uint32_t v : t.entryVertex) ++rowStart_[v + 1];
    for (size_t v = 0; v < vertexCount; ++v) rowStart_[v + 1] += rowStart_[v];
    position_.resize(t.entryVertex.size());
    running_.resize(t.entryVertex.size());
    std::vector<uint32_t> fill(rowStart_.begin(), rowStart_.end() - 1);
    // Visiting sources in leaf order leaves every row sorted by position.
    std::vector<uint32_t> byPosition(sourcePosition.size());
    for (uint32_t s = 0; s < sourcePosition.size(); ++s) byPosition[sourcePosition[s]] = s;
    for (uint32_t p = 0; p < byPosition.size(); ++p) {
      const uint32_t s = byPosition[p];
      for (uint32_t e = t.sourceStart[s]; e < t.sourceStart[s + 1]; ++e) {
        const uint32_t slot = fill[t.entryVertex[e]]++;
        position_[slot] = p;
        running_[slot] = std::max(0.0, static_cast<double>(core::luminance(t.entryTransfer[e])));
      }
    }
    // Running sums in row order (increasing source position).
    for (size_t v = 0; v < vertexCount; ++v) {
      for (uint32_t k = rowStart_[v] + 1; k < rowStart_[v + 1]; ++k) running_[k] += running_[k - 1];
    }
  }

  // Luminance of the transfer from sources at leaf positions [begin, end) to vertex v.
  double rangeSum(uint32_t v, uint32_t begin, uint32_t end) const {
    const auto first = position_.begin() + rowStart_[v];
    const auto last = position_.begin() + rowStart_[v + 1];
    const auto lo = std::lower_bound(first, last, begin);
    const auto hi = std::lower_bound(lo, last, end);
    const auto at = [&](auto it) {
      return it == first ? 0.0 : running_[static_cast<size_t>(it - position_.begin()) - 1];
    };
    return at(hi) - at(lo);
  }

 private:
  std::vector<uint32_t> rowStart_;
  std::vector<uint32_t> position_;
  std::vector<double> running_;
};

void validate(const scene::PatchMesh& mesh, const SourceReceiverSets& sets,
              const RadianceTransfers& t, const ShaftBuildOptions& options) {
  const size_t patches = mesh.patches.size();
  for (uint32_t p : sets.sources) {
    if (p >= patches) inputError("source patch index out of range");
  }
  for (uint32_t p : sets.receivers) {
    if (p >= patches) inputError("receiver patch index out of range");
  }
  if (t.sourceCount() != sets.sources.size()) inputError("sourceStart does not match sources");
  if (t.sourceAverage.size() != sets.sources.size()) inputError("sourceAverage size");
  if (t.vertexRadiance.size() != t.receiverVertices.size()) inputError("vertexRadiance size");
  if (t.entryVertex.size() != t.entryTransfer.size()) inputError("entry arrays differ");
  if (!t.sourceStart.empty() &&
      (t.sourceStart.front() != 0 || t.sourceStart.back() != t.entryVertex.size() ||
       !std::is_sorted(t.sourceStart.begin(), t.sourceStart.end()))) {
    inputError("sourceStart is not a row index");
  }
  for (uint32_t v : t.entryVertex) {
    if (v >= t.receiverVertices.size()) inputError("entry vertex out of range");
  }
  for (uint32_t v : t.receiverVertices) {
    if (v >= mesh.positions.size()) inputError("receiver vertex out of range");
  }
  if (mesh.trianglePatch.size() != mesh.triangleCount()) inputError("trianglePatch size");
  for (uint32_t i : mesh.indices) {
    if (i >= mesh.positions.size()) inputError("triangle index out of range");
  }
  for (uint32_t p : mesh.trianglePatch) {
    if (p >= patches) inputError("triangle patch out of range");
  }
  if (options.maxReceiversPerLeaf == 0) inputError("maxReceiversPerLeaf must be positive");
  if (!(options.pruneFraction >= 0)) inputError("pruneFraction must be >= 0");
}

}  // namespace

ShaftGeometry ShaftGeometry::between(const Aabb& a, const Aabb& b) {
  ShaftGeometry g;
  g.bounds = merged(a, b);
  // Offsets get a margin far above the rounding of a * x + b * y at traversal, so a
  // point of either box can never test outside by an ulp.
  const glm::dvec3 far = glm::max(glm::abs(g.bounds.min), glm::abs(g.bounds.max));
  const double margin = 1e-9 * (1.0 + std::max({far.x, far.y, far.z}));
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      for (int si = 0; si < 2; ++si) {
        for (int sj = 0; sj < 2; ++sj) {
          const Owner oi = faceOwner(corner(a, i, si == 1), corner(b, i, si == 1), si == 1);
          const Owner oj = faceOwner(corner(a, j, sj == 1), corner(b, j, sj == 1), sj == 1);
          if (oi == Owner::kBoth || oj == Owner::kBoth || oi == oj) continue;
          // The line (in the i-j projection) through the two boxes' corresponding
          // corners, its normal turned towards the two faces' outside.
          const double dx = corner(b, i, si == 1) - corner(a, i, si == 1);
          const double dy = corner(b, j, sj == 1) - corner(a, j, sj == 1);
          double na = dy, nb = -dx;
          if (na * (si ? 1.0 : -1.0) + nb * (sj ? 1.0 : -1.0) < 0) {
            na = -na;
            nb = -nb;
          }
          const double len = std::sqrt(na * na + nb * nb);
          na /= len;
          nb /= len;
          // The offset is the largest over both boxes' corners rather than the line's own:
          // equal in exact arithmetic, and it keeps the plane conservative by construction.
          double d = -std::numeric_limits<double>::infinity();
          for (const Aabb* box : {&a, &b}) {
            for (int ci = 0; ci < 2; ++ci) {
              for (int cj = 0; cj < 2; ++cj) {
                d = std::max(d, na * corner(*box, i, ci == 1) + nb * corner(*box, j, cj == 1));
              }
            }
          }
          g.planes[g.planeCount++] =
              ShaftPlane{na, nb, d + margin, static_cast<uint8_t>(i), static_cast<uint8_t>(j)};
        }
      }
    }
  }
  return g;
}

namespace {

// The body of ShaftGeometry::mayIntersect on flattened storage (the per-frame test).
inline bool shaftMayIntersect(const Aabb& bounds, const ShaftPlane* planes, uint32_t count,
                              const Aabb& box) {
  if (box.max.x < bounds.min.x || box.min.x > bounds.max.x || box.max.y < bounds.min.y ||
      box.min.y > bounds.max.y || box.max.z < bounds.min.z || box.min.z > bounds.max.z) {
    return false;
  }
  for (uint32_t k = 0; k < count; ++k) {
    const ShaftPlane& p = planes[k];
    // The box corner deepest into the plane's inside; the box is out when even it is out.
    const double x = p.a >= 0 ? box.min[p.axisI] : box.max[p.axisI];
    const double y = p.b >= 0 ? box.min[p.axisJ] : box.max[p.axisJ];
    if (p.a * x + p.b * y > p.d) return false;
  }
  return true;
}

}  // namespace

bool ShaftGeometry::mayIntersect(const Aabb& box) const {
  return shaftMayIntersect(bounds, planes.data(), planeCount, box);
}

namespace {

// Patch boxes from the patches' own triangles (§6: node bounds are the bounds of the
// geometry, so shafts enclose every point of every patch).
std::vector<Aabb> patchBoxes(const scene::PatchMesh& mesh, const SourceReceiverSets& sets) {
  std::vector<Aabb> patchBox(mesh.patches.size(), Aabb::emptyBox());
  for (size_t tri = 0; tri < mesh.triangleCount(); ++tri) {
    Aabb& box = patchBox[mesh.trianglePatch[tri]];
    for (size_t k = 0; k < 3; ++k) box.extend(mesh.positions[mesh.indices[3 * tri + k]]);
  }
  for (uint32_t p : sets.sources) {
    if (patchBox[p].empty()) inputError("source patch without triangles");
  }
  for (uint32_t p : sets.receivers) {
    if (patchBox[p].empty()) inputError("receiver patch without triangles");
  }
  return patchBox;
}

}  // namespace

// The shaft hierarchy as a temporary tree: recursion decides which children survive before
// the parent is emitted, so it is flattened afterwards.
struct ShaftHierarchy::ShaftTree {
  struct TempShaft {
    uint32_t source, receiver, firstChild, childCount;
  };
  std::vector<TempShaft> temp;
  std::vector<uint32_t> tempChildren;
  uint32_t root = kNoIndex;
};

// §6's significance test of a shaft (source node s, receiver node r), and the budget of
// ShaftBuildOptions::boundLostLight: T(s, v) is the luminance the node's sources send to
// a vertex v of r, lost[v] the luminance pruned at v so far. An insignificant shaft is
// pruned when lost[v] + T(s, v) < pruneFraction x L_v at every v, and T(s, v) is then
// added to lost[v] once per distinct vertex of r. Without the budget lost[] stays 0 and
// every insignificant shaft is pruned. The answers depend on the earlier prunes, so the
// build asks in its fixed order. With pruneFraction = 0 every shaft is significant, even
// one with no transfer at all: culling is then purely geometric.
class ShaftHierarchy::PruneBudget {
 public:
  enum class Fate : uint8_t { kSplit, kPrune, kCoarseLeaf };

  PruneBudget(const scene::PatchMesh& mesh, const RadianceTransfers& transfers,
              std::span<const uint32_t> receiverOrder, std::span<const uint32_t> sourcePosition,
              std::span<const SourceNode> sourceNodes, std::span<const ReceiverNode> receiverNodes,
              const ShaftBuildOptions& options)
      : sourceNodes_(sourceNodes),
        receiverNodes_(receiverNodes),
        pruneFraction_(options.pruneFraction),
        charge_(options.boundLostLight),
        rows_(transfers, sourcePosition) {
    // Receiver vertices of each receiver patch, in octree order, so a receiver node's
    // vertices are one contiguous range; a vertex shared by patches of the node appears
    // more than once, and eachTransfer() visits it once.
    std::vector<uint32_t> receiverVertexOf(mesh.positions.size(), kNoIndex);
    for (uint32_t i = 0; i < transfers.receiverVertices.size(); ++i) {
      receiverVertexOf[transfers.receiverVertices[i]] = i;
    }
    std::vector<std::vector<uint32_t>> patchVertices(mesh.patches.size());
    for (size_t tri = 0; tri < mesh.triangleCount(); ++tri) {
      auto& list = patchVertices[mesh.trianglePatch[tri]];
      for (size_t k = 0; k < 3; ++k) {
        const uint32_t v = receiverVertexOf[mesh.indices[3 * tri + k]];
        if (v != kNoIndex && std::find(list.begin(), list.end(), v) == list.end())
          list.push_back(v);
      }
    }
    vertexStart_.assign(receiverOrder.size() + 1, 0);
    for (size_t k = 0; k < receiverOrder.size(); ++k) {
      const auto& list = patchVertices[receiverOrder[k]];
      nodeVertices_.insert(nodeVertices_.end(), list.begin(), list.end());
      vertexStart_[k + 1] = static_cast<uint32_t>(nodeVertices_.size());
    }
    const size_t vertexCount = transfers.receiverVertices.size();
    threshold_.resize(vertexCount);
    for (size_t v = 0; v < vertexCount; ++v) {
      threshold_[v] =
          pruneFraction_ * static_cast<double>(core::luminance(transfers.vertexRadiance[v]));
    }
    lost_.assign(vertexCount, 0.0);
    seen_.assign(vertexCount, 0);
  }

  // §6 alone: whether the shaft carries at least pruneFraction of L_i at one vertex (the
  // negated comparison makes a NaN L_i significant).
  bool significant(uint32_t s, uint32_t r) {
    if (pruneFraction_ <= 0) return true;
    return !eachTransfer(s, r, [&](uint32_t v, double t) { return t < threshold_[v]; });
  }

  // kSplit when significant; else kPrune, charging the budget, when the shaft fits in it;
  // else kCoarseLeaf.
  Fate fate(uint32_t s, uint32_t r) {
    if (pruneFraction_ <= 0) return Fate::kSplit;
    charges_.clear();
    bool fits = true;
    const bool insignificant = eachTransfer(s, r, [&](uint32_t v, double t) {
      if (!(t < threshold_[v])) return false;
      fits = fits && lost_[v] + t < threshold_[v];
      charges_.push_back({v, t});
      return true;
    });
    if (!insignificant) return Fate::kSplit;
    if (!fits) return Fate::kCoarseLeaf;
    if (charge_) {
      for (const auto& [v, t] : charges_) lost_[v] += t;
    }
    return Fate::kPrune;
  }

 private:
  // Calls visit(v, T(s, v)) once for each distinct receiver vertex v of node r while it
  // returns true; whether it always did.
  template <class Visit>
  bool eachTransfer(uint32_t s, uint32_t r, Visit visit) {
    if (++call_ == 0) {  // the tags wrapped: restart them
      std::fill(seen_.begin(), seen_.end(), 0);
      call_ = 1;
    }
    const SourceNode& sn = sourceNodes_[s];
    const ReceiverNode& rn = receiverNodes_[r];
    for (uint32_t k = vertexStart_[rn.firstPatch]; k < vertexStart_[rn.firstPatch + rn.patchCount];
         ++k) {
      const uint32_t v = nodeVertices_[k];
      if (seen_[v] == call_) continue;
      seen_[v] = call_;
      if (!visit(v, rows_.rangeSum(v, sn.firstLeaf, sn.firstLeaf + sn.leafCount))) return false;
    }
    return true;
  }

  std::span<const SourceNode> sourceNodes_;
  std::span<const ReceiverNode> receiverNodes_;
  double pruneFraction_;
  bool charge_;
  VertexTransferRows rows_;
  std::vector<uint32_t> vertexStart_;
  std::vector<uint32_t> nodeVertices_;
  std::vector<double> threshold_;  // pruneFraction x luminance of L_i, per receiver vertex
  std::vector<double> lost_;       // luminance pruned so far, per receiver vertex
  std::vector<uint32_t> seen_;     // per receiver vertex: the last eachTransfer() that met it
  uint32_t call_ = 0;
  std::vector<std::pair<uint32_t, double>> charges_;  // (v, T(s, v)) of one fate()
};

ShaftHierarchy::ShaftHierarchy(const scene::PatchMesh& mesh, const SourceReceiverSets& sets,
                               const RadianceTransfers& transfers, BuildOptions options) {
  validate(mesh, sets, transfers, options);
  const std::vector<Aabb> patchBox = patchBoxes(mesh, sets);
  buildSourceTree(sets, transfers, patchBox);
  const auto sourceCount = static_cast<uint32_t>(sets.sources.size());
  std::vector<uint32_t> sourcePosition(sourceCount);
  for (uint32_t p = 0; p < sourceCount; ++p) sourcePosition[sourceOrder_[p]] = p;
  buildReceiverTree(sets, patchBox, options.maxReceiversPerLeaf);
  PruneBudget pruning(mesh, transfers, receiverOrder_, sourcePosition, sourceNodes_, receiverNodes_,
                      options);
  flatten(buildShaftTree(pruning));
  shafts_.shrink_to_fit();
  planes_.shrink_to_fit();
  sourceNodes_.shrink_to_fit();
  receiverNodes_.shrink_to_fit();
}

// Source KD-tree (§6): longest axis of the patch centres, median split.
void ShaftHierarchy::buildSourceTree(const SourceReceiverSets& sets,
                                     const RadianceTransfers& transfers,
                                     std::span<const Aabb> patchBox) {
  const auto centre = [&](uint32_t patch) { return patchBox[patch].centre(); };
  const auto sourceCount = static_cast<uint32_t>(sets.sources.size());
  sourceOrder_.resize(sourceCount);
  for (uint32_t s = 0; s < sourceCount; ++s) sourceOrder_[s] = s;
  sourceLeaf_.assign(sourceCount, kNoIndex);
  const auto buildSource = [&](auto& self, uint32_t begin, uint32_t end,
                               uint32_t parent) -> uint32_t {
    const auto index = static_cast<uint32_t>(sourceNodes_.size());
    sourceNodes_.emplace_back();
    SourceNode node;
    node.parent = parent;
    node.firstLeaf = begin;
    node.leafCount = end - begin;
    Aabb centres = Aabb::emptyBox();
    for (uint32_t k = begin; k < end; ++k) {
      const uint32_t patch = sets.sources[sourceOrder_[k]];
      node.bounds = merged(node.bounds, patchBox[patch]);
      centres.extend(centre(patch));
    }
    if (end - begin == 1) {
      node.source = sourceOrder_[begin];
      node.averageTransfer = transfers.sourceAverage[node.source];
      sourceLeaf_[node.source] = index;
    } else {
      const glm::dvec3 extent = centres.size();
      int axis = 0;  // ties go to the lower axis
      if (extent.y > extent[axis]) axis = 1;
      if (extent.z > extent[axis]) axis = 2;
      // Strict total order (centre, patch, source index): the median is unique.
      std::sort(sourceOrder_.begin() + begin, sourceOrder_.begin() + end,
                [&](uint32_t l, uint32_t r) {
                  const double cl = centre(sets.sources[l])[axis];
                  const double cr = centre(sets.sources[r])[axis];
                  if (cl != cr) return cl < cr;
                  if (sets.sources[l] != sets.sources[r]) return sets.sources[l] < sets.sources[r];
                  return l < r;
                });
      const uint32_t mid = begin + (end - begin) / 2;
      node.child[0] = self(self, begin, mid, index);
      node.child[1] = self(self, mid, end, index);
      node.averageTransfer =
          sourceNodes_[node.child[0]].averageTransfer + sourceNodes_[node.child[1]].averageTransfer;
    }
    sourceNodes_[index] = node;
    return index;
  };
  if (sourceCount > 0) buildSource(buildSource, 0, sourceCount, kNoIndex);
}

// Receiver octree (§6): split at the middle of the patch centres' box while a node holds
// more than maxReceiversPerLeaf patches.
void ShaftHierarchy::buildReceiverTree(const SourceReceiverSets& sets,
                                       std::span<const Aabb> patchBox,
                                       uint32_t maxReceiversPerLeaf) {
  const auto centre = [&](uint32_t patch) { return patchBox[patch].centre(); };
  receiverOrder_ = sets.receivers;
  const auto buildReceiver = [&](auto& self, uint32_t index) -> void {
    ReceiverNode node = receiverNodes_[index];
    Aabb centres = Aabb::emptyBox();
    for (uint32_t k = node.firstPatch; k < node.firstPatch + node.patchCount; ++k) {
      node.bounds = merged(node.bounds, patchBox[receiverOrder_[k]]);
      centres.extend(centre(receiverOrder_[k]));
    }
    receiverNodes_[index] = node;
    if (node.patchCount <= maxReceiversPerLeaf) return;
    const glm::dvec3 mid = centres.centre();
    const auto octant = [&](uint32_t patch) {
      const glm::dvec3 c = centre(patch);
      return (c.x > mid.x ? 1 : 0) | (c.y > mid.y ? 2 : 0) | (c.z > mid.z ? 4 : 0);
    };
    const auto first = receiverOrder_.begin() + node.firstPatch;
    const auto last = first + node.patchCount;
    std::sort(first, last, [&](uint32_t l, uint32_t r) {
      const int ol = octant(l), or_ = octant(r);
      return ol != or_ ? ol < or_ : l < r;
    });
    // Coincident centres cannot be separated: keep the node as an oversized leaf rather
    // than recurse forever.
    if (octant(*first) == octant(*(last - 1))) return;
    const auto firstChild = static_cast<uint32_t>(receiverNodes_.size());
    for (auto it = first; it != last;) {
      const int o = octant(*it);
      const auto groupEnd = std::find_if(it, last, [&](uint32_t p) { return octant(p) != o; });
      ReceiverNode child;
      child.firstPatch = static_cast<uint32_t>(it - receiverOrder_.begin());
      child.patchCount = static_cast<uint32_t>(groupEnd - it);
      receiverNodes_.push_back(child);
      it = groupEnd;
    }
    const auto childCount = static_cast<uint32_t>(receiverNodes_.size()) - firstChild;
    receiverNodes_[index].firstChild = firstChild;
    receiverNodes_[index].childCount = childCount;
    for (uint32_t c = 0; c < childCount; ++c) self(self, firstChild + c);
  };
  if (!receiverOrder_.empty()) {
    ReceiverNode root;
    root.patchCount = static_cast<uint32_t>(receiverOrder_.size());
    receiverNodes_.push_back(root);
    buildReceiver(buildReceiver, 0);
  }
}

// Shaft hierarchy (§6), first as a temporary tree: recursion decides which children
// survive before the parent is emitted. Depth first, children in a fixed order: the order
// in which the prune budget is spent.
ShaftHierarchy::ShaftTree ShaftHierarchy::buildShaftTree(PruneBudget& pruning) {
  ShaftTree tree;
  auto& temp = tree.temp;
  auto& tempChildren = tree.tempChildren;
  using TempShaft = ShaftTree::TempShaft;
  // The shafts a split of (s, r) makes: on the node with the larger box (the receiver on a
  // tie), so a shaft narrows where it is widest; a leaf is never split. None when both
  // nodes are leaves.
  using NodePair = std::pair<uint32_t, uint32_t>;
  const auto splitOf = [&](uint32_t s, uint32_t r, std::array<NodePair, 8>& out) -> uint32_t {
    const SourceNode& sn = sourceNodes_[s];
    const ReceiverNode& rn = receiverNodes_[r];
    if (sn.isLeaf() && rn.isLeaf()) return 0;
    const bool splitSource =
        !sn.isLeaf() && (rn.isLeaf() || squaredDiagonal(sn.bounds) > squaredDiagonal(rn.bounds));
    if (splitSource) {
      out[0] = {sn.child[0], r};
      out[1] = {sn.child[1], r};
      return 2;
    }
    for (uint32_t c = 0; c < rn.childCount; ++c) out[c] = {s, rn.firstChild + c};
    return rn.childCount;
  };
  const auto buildShaft = [&](auto& self, uint32_t s, uint32_t r) -> uint32_t {
    using Fate = PruneBudget::Fate;
    const Fate fate = pruning.fate(s, r);
    if (fate == Fate::kPrune) return kNoIndex;
    std::array<NodePair, 8> split{};
    uint32_t splitCount = splitOf(s, r, split);
    // An insignificant shaft the budget cannot take ends as a coarse leaf. So does a
    // significant one none of whose children is significant on its own: its light is
    // spread too thin for §6 to follow, and one coarse leaf costs less than its children
    // as up to 8 (each pruned within the budget or coarse), for a little culling, where
    // there are many small sources (the showroom at 0.1 m patches: 105k shafts, not 178k).
    if (splitCount > 0 &&
        (fate == Fate::kCoarseLeaf ||
         std::none_of(split.begin(), split.begin() + splitCount,
                      [&](const NodePair& c) { return pruning.significant(c.first, c.second); }))) {
      ++coarseLeafShaftCount_;
      splitCount = 0;
    }
    // Children pruned are dropped; the significant one at least is kept.
    std::array<uint32_t, 8> kids{};
    uint32_t kidCount = 0;
    for (uint32_t c = 0; c < splitCount; ++c) {
      const uint32_t k = self(self, split[c].first, split[c].second);
      if (k != kNoIndex) kids[kidCount++] = k;
    }
    const auto first = static_cast<uint32_t>(tempChildren.size());
    tempChildren.insert(tempChildren.end(), kids.begin(), kids.begin() + kidCount);
    temp.push_back(TempShaft{s, r, first, kidCount});
    return static_cast<uint32_t>(temp.size() - 1);
  };
  tree.root =
      sourceNodes_.empty() || receiverNodes_.empty() ? kNoIndex : buildShaft(buildShaft, 0, 0);
  return tree;
}

// Flatten breadth first so each shaft's children are contiguous; planes alongside.
void ShaftHierarchy::flatten(const ShaftTree& tree) {
  const uint32_t tempRoot = tree.root;
  const auto& temp = tree.temp;
  const auto& tempChildren = tree.tempChildren;
  if (tempRoot != kNoIndex) {
    std::vector<uint32_t> tempOf{tempRoot};
    std::vector<uint32_t> depth{1};
    size_t maxDepth = 1;
    const auto emit = [&](uint32_t t) {
      Shaft shaft;
      shaft.sourceNode = temp[t].source;
      shaft.receiverNode = temp[t].receiver;
      const ShaftGeometry g = ShaftGeometry::between(sourceNodes_[shaft.sourceNode].bounds,
                                                     receiverNodes_[shaft.receiverNode].bounds);
      shaft.bounds = g.bounds;
      shaft.firstPlane = static_cast<uint32_t>(planes_.size());
      shaft.planeCount = static_cast<uint8_t>(g.planeCount);
      planes_.insert(planes_.end(), g.planes.begin(), g.planes.begin() + g.planeCount);
      shafts_.push_back(shaft);
    };
    emit(tempRoot);
    for (size_t i = 0; i < shafts_.size(); ++i) {
      const ShaftTree::TempShaft t = temp[tempOf[i]];
      shafts_[i].firstChild = static_cast<uint32_t>(shafts_.size());
      shafts_[i].childCount = static_cast<uint8_t>(t.childCount);
      if (t.childCount == 0) ++leafShaftCount_;
      for (uint32_t c = 0; c < t.childCount; ++c) {
        const uint32_t child = tempChildren[t.firstChild + c];
        tempOf.push_back(child);
        depth.push_back(depth[i] + 1);
        maxDepth = std::max<size_t>(maxDepth, depth[i] + 1);
        emit(child);
      }
    }
    // Depth-first with all children pushed at once: at most 7 siblings wait per level.
    stackBound_ = 8 * maxDepth;
  }
}

void ShaftHierarchy::traverse(const Aabb& objectBox, uint32_t frame, TraversalResult& out) const {
  out.sources.clear();
  out.receivers.clear();
  out.shaftsVisited = 0;
  out.leafShaftsHit = 0;
  TraversalScratch& sc = out.scratch;
  // Tags start one frame behind, so frames counting upwards never meet a stale tag; a
  // repeated frame number would, so it re-initialises them.
  if (sc.sourceTag.size() != sourceCount() || sc.receiverTag.size() != receiverOrder_.size() ||
      !sc.primed || sc.lastFrame == frame) {
    sc.sourceTag.assign(sourceCount(), frame - 1);
    sc.receiverTag.assign(receiverOrder_.size(), frame - 1);
    sc.stack.reserve(stackBound_);
    out.sources.reserve(sourceCount());
    out.receivers.reserve(receiverOrder_.size());
    sc.primed = true;
  }
  sc.lastFrame = frame;
  if (shafts_.empty() || objectBox.empty()) return;

  sc.stack.clear();
  sc.stack.push_back(0);
  while (!sc.stack.empty()) {
    const Shaft& shaft = shafts_[sc.stack.back()];
    sc.stack.pop_back();
    ++out.shaftsVisited;
    if (!shaftMayIntersect(shaft.bounds, planes_.data() + shaft.firstPlane, shaft.planeCount,
                           objectBox)) {
      continue;
    }
    if (shaft.childCount == 0) {
      // §6.1: a leaf shaft puts its source patch and its receiver patches in the lists,
      // once each per frame (a coarse leaf: all of its nodes' sources and patches).
      ++out.leafShaftsHit;
      const SourceNode& sn = sourceNodes_[shaft.sourceNode];
      for (uint32_t k = sn.firstLeaf; k < sn.firstLeaf + sn.leafCount; ++k) {
        const uint32_t s = sourceOrder_[k];
        if (sc.sourceTag[s] != frame) {
          sc.sourceTag[s] = frame;
          out.sources.push_back(s);
        }
      }
      const ReceiverNode& rn = receiverNodes_[shaft.receiverNode];
      for (uint32_t k = rn.firstPatch; k < rn.firstPatch + rn.patchCount; ++k) {
        if (sc.receiverTag[k] != frame) {
          sc.receiverTag[k] = frame;
          out.receivers.push_back(receiverOrder_[k]);
        }
      }
      continue;
    }
    // Reverse push: children are visited in their stored order, which fixes the lists'
    // order.
    for (uint32_t c = shaft.childCount; c-- > 0;) sc.stack.push_back(shaft.firstChild + c);
  }
}

size_t ShaftHierarchy::memoryBytes() const {
  return sizeof(*this) + sourceNodes_.capacity() * sizeof(SourceNode) +
         receiverNodes_.capacity() * sizeof(ReceiverNode) + shafts_.capacity() * sizeof(Shaft) +
         planes_.capacity() * sizeof(ShaftPlane) +
         (sourceOrder_.capacity() + receiverOrder_.capacity() + sourceLeaf_.capacity()) *
             sizeof(uint32_t);
}

}  // namespace penumbra::shadow
