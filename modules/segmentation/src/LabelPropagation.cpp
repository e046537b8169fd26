#include "rasm/segmentation/LabelPropagation.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "rasm/compute/Parallel.h"

namespace rasm::segmentation {

namespace {

/// Whether pixels whose depths sum to depth_sum lie, on average, within max_depth_m (0 = any
/// range): the range gate of the merge evidence and of the split rule (merge_max_depth_m).
bool withinDepth(float depth_sum, int pixels, double max_depth_m) {
  return max_depth_m <= 0.0 || depth_sum <= float(max_depth_m) * float(pixels);
}

/// Pi restricted to one current label: a few map labels, each with its pixels and their depths
/// summed (the merge evidence is range-gated, merge_max_depth_m).
struct Overlaps {
  struct Entry {
    std::uint32_t label;
    int pixels;
    float depth_sum;
  };
  std::vector<Entry> counts;
  int labelled = 0;  ///< pixels with a map label
  void add(std::uint32_t r, float z) {
    ++labelled;
    for (Entry& e : counts)
      if (e.label == r) {
        ++e.pixels;
        e.depth_sum += z;
        return;
      }
    counts.push_back({r, 1, z});
  }
  /// Index of the entry with the most pixels (the first of equals); counts must not be empty.
  std::size_t best() const {
    std::size_t bi = 0;
    for (std::size_t i = 1; i < counts.size(); ++i)
      if (counts[i].pixels > counts[bi].pixels) bi = i;
    return bi;
  }
};

/// L^r on the grid of every `step`-th pixel (in x and y) of the frame: the label of the candidate
/// nearest to the measured depth within the gate.
void renderLabels(const Image<Vec3f>& vertex_cam, const fusion::IndexMapView& view,
                  const maps::SurfelArrays& s, const TSegmentationParams& p, int step,
                  Image<std::uint32_t>& out) {
  const int w = vertex_cam.width(), h = vertex_cam.height();
  const int gw = (w + step - 1) / step, gh = (h + step - 1) / step;
  out.resize(gw, gh);
  const bool have = view.valid() && view.width() == w && view.height() == h;
  const float gate_abs = float(p.render_depth_gate_m), gate_rel = float(p.render_depth_gate_rel);
  compute::forEach1D(gh, [&](int gy) {
    std::uint32_t* o = out.row(gy);
    const int y = gy * step;
    const Vec3f* v = vertex_cam.row(y);
    for (int gx = 0; gx < gw; ++gx) {
      const int x = gx * step;
      o[gx] = 0u;
      if (!have || std::isnan(v[x].x())) continue;
      const float z = v[x].z(), gate = gate_abs + gate_rel * z;
      float best = gate;
      int bi = -1;
      view.forEachCandidate(x, y, [&](int i, float zc) {
        const float d = std::fabs(zc - z);
        if (d <= best) {
          best = d;
          bi = i;
        }
      });
      if (bi >= 0) o[gx] = s.segment[bi];
    }
  });
}

/// Map label a current segment takes instead of its best one (0 = none: a new label), or
/// kKeepBest, per current label (split_max_share). The best map label is another current
/// segment's (that one holds most of its pixels in view) and this segment holds less than
/// split_max_share of them, near enough to resolve the edge between the two (merge_max_depth_m):
/// the map had joined it to its neighbour (an object first fused into the table's label from
/// afar) and this view separates them. Without this rule the best-overlap rule hands the object
/// its support's label in every later frame, for ever. The segment then takes the largest map
/// label under it that no other segment holds most of (the label a previous split gave it), so a
/// split does not mint a new label every frame.
constexpr std::uint32_t kKeepBest = ~0u;
std::vector<std::uint32_t> splitOffSegments(const std::vector<Overlaps>& pi,
                                            const TSegmentationParams& p, int area) {
  std::vector<std::uint32_t> take(pi.size(), kKeepBest);
  if (p.split_max_share <= 0.0) return take;
  // Per map label: pixels in view over all current segments, and the segment holding the most.
  struct Owner {
    int total = 0, best_n = 0, segment = 0;
  };
  std::unordered_map<std::uint32_t, Owner> owner;
  for (std::size_t l = 1; l < pi.size(); ++l)
    for (const Overlaps::Entry& e : pi[l].counts) {
      Owner& o = owner[e.label];
      o.total += e.pixels;
      if (e.pixels > o.best_n) {
        o.best_n = e.pixels;
        o.segment = int(l);
      }
    }
  for (std::size_t l = 1; l < pi.size(); ++l) {
    const Overlaps& o = pi[l];
    if (o.counts.empty()) continue;
    float depth = 0.f;
    for (const Overlaps::Entry& e : o.counts) depth += e.depth_sum;
    const Overlaps::Entry& best = o.counts[o.best()];
    const Owner& b = owner.at(best.label);
    if (!withinDepth(depth, o.labelled, p.merge_max_depth_m) || b.segment == int(l) ||
        best.pixels >= p.split_max_share * b.total || o.labelled * area < p.split_min_px)
      continue;
    std::uint32_t own = 0;
    int own_n = 0;
    for (const Overlaps::Entry& e : o.counts)
      if (owner.at(e.label).segment == int(l) && e.pixels > own_n &&
          e.pixels * area >= p.propagation_min_overlap_px) {
        own = e.label;
        own_n = e.pixels;
      }
    take[l] = own;
  }
  return take;
}

}  // namespace

void propagateLabels(const FrameSegments& seg, const Image<Vec3f>& vertex_cam,
                     const fusion::IndexMapView& view, const maps::SurfelArrays& surfels,
                     const TSegmentationParams& p, std::uint32_t& next_label, Propagation& out) {
  const int w = seg.labels.width(), h = seg.labels.height();
  // Pi is counted on every `step`-th pixel (L_t comes from the segmentation level, so a finer
  // count adds nothing); pixel thresholds are scaled to full-resolution pixels.
  const int step = std::max(1, p.propagation_step_px);
  renderLabels(vertex_cam, view, surfels, p, step, out.rendered);

  // Pi: per current label, the map labels under it (serial: increments on short lists).
  std::vector<Overlaps> pi(std::size_t(seg.count) + 1);
  for (int gy = 0; gy < out.rendered.height(); ++gy) {
    const std::uint32_t* l = seg.labels.row(gy * step);
    const std::uint32_t* r = out.rendered.row(gy);
    const Vec3f* v = vertex_cam.row(gy * step);
    for (int gx = 0; gx < out.rendered.width(); ++gx) {
      const std::uint32_t lx = l[gx * step];
      if (lx && r[gx]) pi[lx].add(r[gx], v[gx * step].z());
    }
  }
  const int area = step * step;
  const std::vector<std::uint32_t> split = splitOffSegments(pi, p, area);
  out.label_of.assign(std::size_t(seg.count) + 1, 0u);
  out.matched = out.created = 0;
  out.cosegmented.clear();
  std::vector<std::pair<std::uint32_t, int>> visible_px;
  for (int l = 1; l <= seg.count; ++l) {
    const Overlaps& o = pi[l];
    std::vector<std::uint32_t> shared;
    for (const Overlaps::Entry& e : o.counts) {
      const int n = e.pixels * area;
      visible_px.emplace_back(e.label, n);
      // Beyond merge_max_depth_m the edge test's noise margins (z^2) exceed the folds and steps
      // between objects, so sharing a segment there is no evidence that two labels are one.
      if (withinDepth(e.depth_sum, e.pixels, p.merge_max_depth_m) &&
          n >= p.propagation_min_overlap_px && n >= p.merge_min_fraction * o.labelled * area)
        shared.push_back(e.label);
    }
    const Overlaps::Entry* top = o.counts.empty() ? nullptr : &o.counts[o.best()];
    const std::uint32_t best = top ? top->label : 0u;
    const int best_n = top ? top->pixels * area : 0;
    const std::uint32_t split_to = split[std::size_t(l)];
    if (best && best_n >= p.propagation_min_overlap_px &&
        best_n >= p.propagation_min_overlap * o.labelled * area && split_to != 0u) {
      out.label_of[l] = split_to == kKeepBest ? best : split_to;
      ++out.matched;
    } else {
      out.label_of[l] = next_label++;
      ++out.created;
    }
    std::sort(shared.begin(), shared.end());
    for (std::size_t a = 0; a < shared.size(); ++a)
      for (std::size_t b = a + 1; b < shared.size(); ++b)
        out.cosegmented.emplace_back(shared[a], shared[b]);
  }
  std::sort(out.cosegmented.begin(), out.cosegmented.end());
  out.cosegmented.erase(std::unique(out.cosegmented.begin(), out.cosegmented.end()),
                        out.cosegmented.end());
  // Map labels in view: pixels summed over the current segments.
  std::sort(visible_px.begin(), visible_px.end());
  out.visible.clear();
  for (std::size_t i = 0; i < visible_px.size();) {
    std::size_t j = i;
    int n = 0;
    while (j < visible_px.size() && visible_px[j].first == visible_px[i].first)
      n += visible_px[j++].second;
    if (n >= p.propagation_min_overlap_px) out.visible.push_back(visible_px[i].first);
    i = j;
  }

  out.propagated.resize(w, h);
  compute::forEach1D(h, [&](int y) {
    const std::uint32_t* l = seg.labels.row(y);
    std::uint32_t* o = out.propagated.row(y);
    for (int x = 0; x < w; ++x) o[x] = out.label_of[l[x]];
  });
}

}  // namespace rasm::segmentation
