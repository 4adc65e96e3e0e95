/**
 * @file synth.h
 * @brief Synthetic actors performing the IAS-Lab Action Dataset's 15 actions, continuous streams of
 *        those actions, and the MSR Action3D skeletons (alone or in a row), rendered by the virtual Kinect (scene.h) one
 *        sample at a time, in process. ROS-free. This is the API the training, evaluation,
 *        benchmark and tracker tests use.
 *
 * Typical use:
 * @code
 *   for (const auto& spec : action_flow::synth::iasLabSamples()) {
 *     action_flow::synth::SampleRenderer sample(spec);
 *     action_flow::Cloud cloud;
 *     std::vector<std::uint8_t> mask;
 *     for (int i = 0; i < sample.frames(); ++i) {
 *       sample.render(i, cloud, &mask);   // organized 640x480, camera_rgb_optical_frame, NaN = no depth
 *       ... sample.stamp(i), sample.label(), sample.skeleton(i) ...
 *     }
 *   }
 * @endcode
 */
#pragma once

#include <action_flow/synth/scene.h>
#include <action_flow/synth/skeleton.h>
#include <action_flow/types.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace action_flow
{
namespace synth
{
/** @brief The 15 IAS-Lab actions in snake_case, alphabetical: check_watch ... wave. */
const std::vector<std::string>& iasLabActions();

/** The changes a training copy of an MSR sample makes (SampleSpec::copy_changes). */
enum CopyChange : unsigned
{
  kCopyBody = 1u,      ///< another body and clothes
  kCopyPace = 2u,      ///< 0.8-1.2 times as fast
  kCopyTurn = 4u,      ///< turned -30..30 degrees
  kCopyDistance = 8u,  ///< placed 1.5-4.5 m away
  kCopyAll = 15u
};

/**
 * @brief One sample to render.
 *
 * dataset "stream": one actor of the "ias" set (person "pNN") performing stream_actions actions in
 * a row (about a minute for 8), with transitions and idle periods between them; repetition is the
 * stream's number and action is "stream".
 *
 * dataset "msr_stream": real motion in a row. Either an MSR Action3D subject ("sNN") performing
 * stream_actions of their own sequences (msrStreamSequences), skeleton_file being the MSR folder,
 * with idle periods between them; repetition is the stream's number. Or, with segments_file, one
 * continuous skeleton file in the MSR format (skeleton_file) with its truth. action is "stream".
 */
struct SampleSpec
{
  /** "ias" (synthetic actors), "stream" (their streams), "msr" (MSR Action3D skeletons),
   *  "msr_stream" (MSR motion in a row), "crowd" (several people at once: CrowdRenderer) or "clutter"
   *  (cluttered rooms, clutter.h). */
  std::string dataset = "ias";
  std::string person;           ///< "p01".."pNN" (ias, stream) or "s01".."s10" (msr, msr_stream)
  std::string action;           ///< an iasLabActions() name, an msrActions() name, or "stream"
  int repetition = 1;           ///< 1-based; the take for msr, the stream's number for the streams
  std::uint64_t seed = 1;       ///< dataset seed: same seed, same actors and same frames
  /** msr: the skeleton file; msr_stream: the MSR folder, or (with segments_file) one skeleton file. */
  std::string skeleton_file;
  /**
   * msr_stream with one continuous skeleton file: its truth, a CSV of rows
   * "action,first_frame,last_frame" (an optional header line of that text first) in the file's own
   * 15 fps frames, inclusive, ordered and not overlapping.
   */
  std::string segments_file;
  /** Render only the first max_frames frames (0 = all); for tests and previews. */
  int max_frames = 0;
  /** stream, msr_stream: the number of actions performed (1..99; sit_down + get_up count as two). */
  int stream_actions = 8;
  /** msr_stream from the folder: the msrActions() its sequences are drawn from (empty: all 20). */
  std::vector<std::string> stream_pool;
  /** crowd (CrowdRenderer, crowd.h): the number of people (2..5; repetition is the scene's number). */
  int crowd_people = 3;
  /** crowd: the scene's length (s). */
  double crowd_seconds = 60.0;

  /** clutter: the scene type, a clutterKinds() name (clutter.h); person "none" and action "none" for
   *  furniture only. */
  std::string scene;

  /**
   * ias: which way the actor faces, in degrees from facing the camera (0: towards it, 90: side on,
   * 180: the back to the camera), with a uniform spread of +-facing_spread around it. A non-zero
   * facing turns the actor to its left or its right (drawn from the sample's name), and the same
   * performance is rendered whatever the facing (the cross-view evaluation sees one motion from
   * several sides). The default, 0 +- 30, is the set's usual placement.
   */
  double facing = 0.0;
  double facing_spread = 30.0;

  /**
   * msr: 0 for the recording itself; k >= 1 for its k-th training copy (training-time augmentation,
   * docs/synth.md "Training copies"): the same recorded motion rendered again with another body and
   * clothes (makeActor of another seed; the height stays the skeleton's), paced 0.8-1.2 times as fast,
   * turned -30..30 degrees about the body's vertical axis and placed 1.5-4.5 m from the camera (moved
   * back until the whole body is in view), each drawn from the spec. The name ends in "_c<k>".
   */
  int copy = 0;
  /** Which of a training copy's changes are made (CopyChange bits; default all). With fewer, the
   *  name ends in "_c<k>_" and a letter per change made (b, p, t, d); each change draws the same
   *  value whichever others are made. */
  unsigned copy_changes = kCopyAll;

  /**
   * @brief "p01_wave_1" / "a01_s01_e01" / "p01_stream_1" / "s01_msr_stream_1" (a continuous file:
   *        its file name without extension, file-name safe) / "crowd3_1" (people, scene) /
   *        "wall_03" (clutter: scene type and number): unique within a dataset, used as the bag's base name.
   *        An ias sample placed other than by default ends in "_f<facing>s<spread>" ("p01_wave_1_f90s0"),
   *        an msr training copy in "_c<copy>" ("a01_s01_e01_c2").
   */
  std::string name() const;
};

/**
 * @brief The IAS-Lab-style set: people x 15 actions x repetitions, ordered person, action, repetition.
 * @throws std::invalid_argument if people is not in 1..99 or repetitions not in 1..99
 */
std::vector<SampleSpec> iasLabSamples(int people = 12, int repetitions = 3, std::uint64_t seed = 1);

/**
 * @brief The MSR Action3D set from a folder of aAA_sSS_eEE_skeleton3D.txt files, sorted by name.
 *        With @p cvpr12_only and a files_used_in_cvpr12_paper.txt in the folder, only the 557
 *        sequences it lists (the others include untracked or broken recordings).
 * @throws std::runtime_error if the folder cannot be read or holds no skeleton file
 */
std::vector<SampleSpec> msrSamples(const std::string& folder, std::uint64_t seed = 1, bool cvpr12_only = true);

/**
 * @brief The streams: persons p<first_person>..p<first_person + people - 1>, each performing
 *        @p streams streams of @p actions actions, ordered person then stream.
 * @throws std::invalid_argument if a person number would leave 1..99, or people, streams or
 *         actions is not in 1..99
 */
std::vector<SampleSpec> streamSamples(int first_person, int people, int streams, int actions = 8, std::uint64_t seed = 1);

/**
 * @brief The actions stream @p spec performs, in order (the actions of its segments); cheap, no motion.
 *
 * Drawn from the 14 IAS-Lab actions other than standing (the idle periods are standing), from one
 * shuffle bag sequence per person and seed that the person's streams take in turn (stream 1 the
 * first stream_actions, stream 2 the next, ...; so over a person's streams every action appears
 * equally often). sit_down + get_up are one item of the bag and always consecutive, get_up appears
 * nowhere else, and no action follows itself.
 * @throws std::invalid_argument if spec is not a valid stream (dataset, person, number, actions)
 */
std::vector<std::string> streamActions(const SampleSpec& spec);

/**
 * @brief The MSR streams: subjects ("s01".."s10") x @p streams streams of @p actions sequences each,
 *        ordered subject then stream; skeleton_file = @p folder. @p pool: the msrActions() the
 *        sequences are drawn from (empty: all 20).
 * @throws std::invalid_argument if streams or actions is not in 1..99, a subject id is malformed, a
 *         pool name is unknown, or a subject has fewer than streams x actions sequences;
 *         std::runtime_error if the folder cannot be read (msrSamples)
 */
std::vector<SampleSpec> msrStreamSamples(const std::string& folder, const std::vector<std::string>& subjects,
                                         int streams, int actions, std::uint64_t seed = 1,
                                         const std::vector<std::string>& pool = {});

/**
 * @brief The MSR sequences ("msr" samples) msr_stream @p spec performs, in order; cheap, no motion.
 *
 * The subject's sequences of the cvpr12 list (msrSamples), restricted to the spec's stream_pool,
 * are dealt from one sequence per person and seed that the subject's streams take in turn (stream 1
 * the first stream_actions, stream 2 the next, ...): rounds of one take of every action (takes and
 * actions shuffled), so each sequence is used at most once and the actions spread evenly over the
 * streams; no action follows itself where a round allows it.
 * @throws std::invalid_argument if spec is not an msr_stream from a folder (dataset, person, number,
 *         actions, pool), or the subject has too few sequences for this stream
 */
std::vector<SampleSpec> msrStreamSequences(const SampleSpec& spec);

/** @brief One performed action of a sample: frame indices, inclusive. */
struct StreamSegment
{
  std::string action;
  int first = 0;
  int last = 0;
};

/** @brief A synthetic person of the "ias" set: looks, body and style of moving. */
struct Actor
{
  std::string id;          ///< "p01"
  BodyShape shape;
  Appearance appearance;
  bool left_handed = false;
  float pace = 1.0f;       ///< speed factor of every movement (>1 faster)
  float amplitude = 1.0f;  ///< size factor of gestures
  float sway = 1.0f;       ///< idle sway factor
  std::uint64_t style_seed = 0;  ///< person-specific shape of the gestures
};

/** @brief The actor with this id ("p01".."p99") for this dataset seed; deterministic. */
Actor makeActor(const std::string& id, std::uint64_t seed = 1);

/**
 * @brief Renders one sample: builds the actor (or reads the skeleton file), the motion, the camera
 *        pose and the room at construction; then renders any frame on demand.
 *
 * Construction costs a few tens of milliseconds (motion and room ray-casting). All const methods
 * are thread-safe; different renderers are independent. Output depends only on the spec.
 */
class SampleRenderer
{
public:
  /**
   * @throws std::invalid_argument on an unknown dataset, action or person id, or an invalid stream;
   *         std::runtime_error from the MSR parser, if an MSR file has no tracked frame, or on a
   *         malformed segments file ("<path>:<line>: <what>")
   */
  explicit SampleRenderer(const SampleSpec& spec, const CameraModel& camera = CameraModel());
  ~SampleRenderer();

  const SampleSpec& spec() const;
  /** @brief The action label (the spec's action; "stream" for the streams). */
  const std::string& label() const;
  int frames() const;
  /** @brief Stamp of frame @p i in seconds: a fixed start (2013-01-01 UTC) + i / fps. */
  double stamp(int i) const;

  /**
   * @brief Ground truth of what is performed when, ordered, inside [0, frames()).
   *
   * stream: one segment per performed action, its core: the frames between the performance's own
   * idle lead-in and lead-out (idle periods and transitions belong to no segment); segments past
   * max_frames are dropped, the one it cuts is clipped. msr_stream: one segment per MSR sequence,
   * the whole sequence (they are pre-segmented), or the segments file's rows (15 fps frame f is
   * frame 2f here). ias and msr: one segment, the whole sample, with the sample's action.
   */
  const std::vector<StreamSegment>& segments() const;
  /**
   * @brief The action of the segment holding frame @p i, or "" if none does (idle, transition).
   * @throws std::out_of_range if i is not in [0, frames())
   */
  std::string actionAt(int i) const;

  /**
   * @brief Renders frame @p i as an organized cloud (width x height, camera_rgb_optical_frame, stamp in
   *        pcl microseconds, NaN xyz where no depth, colour everywhere) and, if @p mask is given,
   *        the person id per pixel (row-major, 1 = the actor, 0 = background; set where the person's
   *        surface is seen, whether or not the sensor returned depth there).
   * @throws std::out_of_range if i is not in [0, frames())
   */
  void render(int i, Cloud& out, std::vector<std::uint8_t>* mask = nullptr) const;
  /** @brief Frame @p i as images (depth in metres, RGB, mask). */
  void renderImages(int i, FrameImages& out) const;

  /** @brief The 15 joints of frame @p i in the camera's optical frame (metres). */
  Skeleton skeleton(int i) const;
  /** @brief The 15 joints of frame @p i in the world frame (floor origin below the camera, z up). */
  const Skeleton& worldSkeleton(int i) const;

  /**
   * @brief The person of frame @p i as a body for SceneRenderer, with mask id @p id: to compose
   *        scenes of several people (e.g. for tracker tests), pose bodies of several samples, move
   *        them apart (PosedBody::joints is in the world frame) and render them with one
   *        SceneRenderer. The body refers to this renderer's appearance: keep the renderer alive.
   */
  PosedBody posedBody(int i, std::uint8_t id = 1) const;

  /** @brief People rendered in each frame: 1, or 0 for a clutter scene of furniture only (then
   *         render() draws the room alone and the skeletons are not meaningful). */
  int bodies() const;

  /** @brief The camera (with this sample's height and tilt). */
  const CameraModel& camera() const;
  const SceneRenderer& scene() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace synth
}  // namespace action_flow
