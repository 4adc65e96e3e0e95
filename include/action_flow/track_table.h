/**
 * @file track_table.h
 * @brief The per-track state of a stage, keyed by track id, with the one set of rules that the
 *        flow and classifier nodelets and the offline extraction all follow.
 */
#pragma once

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace action_flow
{
/**
 * @brief Each track's State, and when it ends. Before each frame's people, begin() applies the
 *        rules, in this order:
 *        - a reset from upstream, or a frame stamped before the previous one (a bag looping),
 *          ends every track (cleared);
 *        - a track that the tracker reports lost ends;
 *        - a track not seen for 10 max_gap ends (its lost report may have been dropped).
 *        A frame within max_gap of a track's last one continues its flow; that rule is
 *        FlowTrack's, with the same max_gap (FlowParams::max_gap).
 */
template <class State>
class TrackTable
{
public:
  struct Frame
  {
    bool cleared = false;          ///< every track ended (reset or time going backwards)
    bool time_went_back = false;   ///< the frame is stamped before the previous one
    double previous_stamp = -1.0;  ///< the previous frame's stamp (-1: none)
    /** The tracks that ended, in id order, with their state (cleared: all of them). */
    std::vector<std::pair<std::uint32_t, State>> ended;
  };

  explicit TrackTable(double max_gap) : max_gap_(max_gap) {}

  /** @brief Starts the frame stamped @p stamp: applies the rules above. */
  Frame begin(double stamp, bool reset, const std::vector<std::uint32_t>& lost)
  {
    Frame f;
    f.previous_stamp = last_stamp_;
    f.time_went_back = last_stamp_ >= 0.0 && stamp < last_stamp_;
    last_stamp_ = stamp;
    f.cleared = reset || f.time_went_back;
    for (auto it = tracks_.begin(); it != tracks_.end();)
    {
      bool ends = f.cleared || stamp - it->second.last_seen > 10.0 * max_gap_;
      for (std::uint32_t id : lost)
        ends = ends || id == it->first;
      if (!ends)
      {
        ++it;
        continue;
      }
      f.ended.emplace_back(it->first, std::move(it->second.state));
      it = tracks_.erase(it);
    }
    return f;
  }

  /** @brief Track @p id's state, made by @p make() when the track is new; marks it seen now. */
  template <class Make>
  State& at(std::uint32_t id, Make make)
  {
    auto it = tracks_.find(id);
    if (it == tracks_.end())
      it = tracks_.emplace(id, Entry{ make(), last_stamp_ }).first;
    it->second.last_seen = last_stamp_;
    return it->second.state;
  }

  /** @brief Ends every track now (end of input), returning them in id order. */
  std::vector<std::pair<std::uint32_t, State>> endAll()
  {
    std::vector<std::pair<std::uint32_t, State>> out;
    for (auto& kv : tracks_)
      out.emplace_back(kv.first, std::move(kv.second.state));
    tracks_.clear();
    return out;
  }

  std::size_t size() const { return tracks_.size(); }
  double maxGap() const { return max_gap_; }

private:
  struct Entry
  {
    State state;
    double last_seen;
  };
  double max_gap_;
  double last_stamp_ = -1.0;
  std::map<std::uint32_t, Entry> tracks_;
};

}  // namespace action_flow
