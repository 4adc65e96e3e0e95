/**
 * @file temporal_pyramid.h
 * @brief The default recognizer's sequence descriptor: which parts of the posture-and-flow frame
 *        descriptor it uses, and a temporal pyramid of their means, maxima and Fourier magnitudes that
 *        does not depend on the number of frames or on how fast the action was performed.
 */
#pragma once

#include <action_flow/posture_flow.h>

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace action_flow
{
/** @brief The classifier that follows the pyramid. */
enum class PyramidClassifier
{
  Linear,  ///< multinomial-calibrated one-vs-rest logistic regression (liblinear), a probability per label
  Nearest  ///< 1-NN by Euclidean distance (ActionClassifier), kept for comparison
};

template <>
struct EnumNames<PyramidClassifier>
{
  static constexpr const char* names[] = { "linear", "nn" };
};
std::string toString(PyramidClassifier c);
/** @throws std::invalid_argument for a name other than "linear" or "nn". */
PyramidClassifier pyramidClassifierFromString(const std::string& name);

/** @brief How the flow of a cell enters the sequence descriptor. */
enum class FlowEncoding : std::uint8_t
{
  Sums = 0,   ///< the 3 signed sums of the components (the paper's SUMFLOW per cell, not normalised)
  Bins = 1,   ///< the 6 direction bins (+x, -x, +y, -y, +z, -z): a back-and-forth motion does not cancel out
  Choose = 2  ///< by cross-validation inside the training people
};
template <>
struct EnumNames<FlowEncoding>
{
  static constexpr const char* names[] = { "sums", "bins", "choose" };
};

/** @brief Whether training adds mirrored copies of the samples. */
enum class MirrorMode : std::uint8_t
{
  Off = 0,
  On = 1,
  Choose = 2  ///< by cross-validation inside the training people
};
template <>
struct EnumNames<MirrorMode>
{
  static constexpr const char* names[] = { "off", "on", "choose" };
};

/**
 * @brief Whether the sequence descriptor holds the cells' shares of the body's points. The names
 *        are those of a bool, so model files written when this was one still load.
 */
enum class PostureMode : std::uint8_t
{
  Off = 0,
  On = 1,
  Choose = 2  ///< by cross-validation inside the training people
};
template <>
struct EnumNames<PostureMode>
{
  static constexpr const char* names[] = { "false", "true", "choose" };
};

/** @brief The most Fourier coefficients a pyramid part may hold. */
constexpr int kMaxFourier = 16;

/** @brief What each part of the temporal pyramid holds of its frames besides their mean. */
struct Pooling
{
  bool maxima = false;  ///< their maximum, value by value
  /**
   * The magnitudes of the first `fourier` coefficients of their discrete Fourier transform,
   * value by value: for k = 1..fourier, |sum_j (x_j - mean) e^(-2 pi i k j / n)| / n over the
   * part's n frames (a Fourier temporal pyramid; the mean is coefficient 0, and a k that aliases
   * to it, a multiple of n, gives 0 up to rounding). Where k > n / 2, |X_k| repeats |X_(n-k)|. A magnitude does not change when the
   * motion shifts in time within the part, and it tells a slow sweep from a fast repeated one.
   */
  int fourier = 0;
  /** @brief Values each part holds per frame value: the mean, then the maxima, then the magnitudes. */
  int blocks() const { return 1 + (maxima ? 1 : 0) + fourier; }
};

/**
 * @brief Every switch of the default recognizer after the frame descriptor. Each part can be
 *        turned off for an ablation; none of them changes the frame descriptors, so the
 *        ablations share one extraction.
 */
struct PyramidParams
{
  /**
   * Use the cells' shares of the body's points. Choose: decided with C by the cross-validation over
   * the training people (the shares place a still arm, and they also carry each person's build:
   * with few training people they can teach the model who, not what). On by default: choosing
   * doubles the cross-validation's cost, and on MSR Action3D it kept posture on all 20, AS1 and
   * AS2 and dropped it on AS3, where that cost 8 points (docs/evaluation.md).
   */
  PostureMode posture = PostureMode::On;
  FlowEncoding flow = FlowEncoding::Choose;  ///< direction bins or signed sums per cell
  bool coarse_to_fine = true;       ///< cells at 1, 2 and 4 parts per axis; false: 4 only
  /** Use the body-geometry block (centroid, extremes, where the flow is and how it turns); models
   *  of format version 2 predate it and load with false. */
  bool geometry = true;
  /**
   * What the geometry block is multiplied by. Its coordinates are about ten times the cells'
   * shares, and the linear classifier standardises all inputs by one overall spread, so at full
   * weight they swamp the cells (and carry each person's build into the model). 0.1 was chosen on
   * MSR Action3D's training subjects alone, leave-one-subject-out (docs/evaluation.md).
   */
  float geometry_weight = 0.1f;
  int temporal_levels = 3;          ///< pyramid levels: 1 = whole sequence, 2 = + halves, 3 = + quarters
  /**
   * Each part of the pyramid holds its frames' maxima beside their means: a mean smears a short
   * motion (a punch, a catch) over its part, its peak stays. Chosen on MSR Action3D's training
   * subjects alone, leave-one-subject-out: 63.4% with means only, 69.7% with maxima beside them
   * (docs/evaluation.md). Models of format 5 and older predate it and load with false.
   */
  bool max_pooling = true;
  /**
   * Each part of the pyramid also holds the magnitudes of its frames' first N Fourier coefficients
   * (Pooling::fourier): how much each value swings, and how fast, wherever in the part it
   * happens. Chosen on MSR Action3D's training subjects alone, leave-one-subject-out: 69.7% with
   * none, 72.9 / 73.2 / 75.4 / 75.0% with 3 / 4 / 6 / 8 (docs/evaluation.md). Models of format 6
   * and older predate it and load with 0.
   */
  int fourier = 6;
  PyramidClassifier classifier = PyramidClassifier::Linear;
  /** Regularisation of the linear classifier; 0 = chosen by cross-validation inside the training people. */
  double c = 0.0;
  /**
   * Training-time augmentation: every sample added mirrored left to right (label unchanged).
   * Choose: decided with C by the cross-validation over the training people (it helps where
   * people use either arm, and hurts where everyone uses the same one); the model records the choice.
   */
  MirrorMode mirror = MirrorMode::Choose;

  template <class Self, class V>
  static void visit(Self& p, V&& v)
  {
    v("pyramid/posture", p.posture, "use the cells' shares of the body's points (choose: by cross-validation)",
      Shapes::Model);
    v("pyramid/flow", p.flow, "a cell's flow as direction bins or signed sums (choose: by cross-validation)",
      Shapes::Model);
    v("pyramid/coarse_to_fine", p.coarse_to_fine, "cells at 1, 2 and 4 parts per axis (false: 4 only)",
      Shapes::Model);
    v("pyramid/geometry", p.geometry, "use the body-geometry block", Shapes::Model);
    v("pyramid/geometry_weight", p.geometry_weight, "what the geometry block is multiplied by", Shapes::Model);
    v("pyramid/temporal_levels", p.temporal_levels, "1 = whole sequence, 2 = + halves, 3 = + quarters",
      Shapes::Model);
    v("pyramid/max_pooling", p.max_pooling, "each part holds its frames' maxima beside their means", Shapes::Model);
    v("pyramid/fourier", p.fourier,
      "each part holds the magnitudes of its frames' first N Fourier coefficients (0 = none)", Shapes::Model);
    v("pyramid/classifier", p.classifier, "logistic regression (liblinear) or 1-NN", Shapes::Model);
    v("pyramid/c", p.c, "the linear classifier's C; 0 = by cross-validation over the training people",
      Shapes::Model);
    v("pyramid/mirror", p.mirror, "training adds mirrored copies (choose: by cross-validation)", Shapes::Model);
  }

  /** @brief What each part of the pyramid holds (max_pooling and fourier). */
  Pooling pooling() const { return Pooling{ max_pooling, fourier }; }

  /** @brief What is wrong with these values (levels, Fourier coefficients, weights out of range), or "". */
  std::string problem() const;
};

/**
 * @brief The part of a full posture-and-flow frame descriptor that @p params use.
 * @throws std::invalid_argument if @p full does not have @p layout's length, or params.flow or
 *         params.posture is still Choose
 */
Eigen::VectorXf selectFrameFeatures(const Eigen::VectorXf& full, const PostureFlowDescriptor& layout,
                                    const PyramidParams& params);

/**
 * @brief The temporal pyramid: level l cuts the sequence's time span [t_first, t_last] into 2^l
 *        equal parts; each part gives the mean of the frames whose stamps fall in it (the frame
 *        nearest its middle when none does), then, as @p pooling asks, their maximum and the
 *        magnitudes of their Fourier coefficients, value by value. Parts are concatenated, whole sequence first, then
 *        halves, then quarters; with @p power each value v becomes sign(v) sqrt(|v|) (a power
 *        normalisation that keeps large motions from swamping small ones). ActionModel applies it
 *        to every value of the default recognizer, the geometry block's coordinates too (leaving
 *        those plain made no difference on MSR Action3D's training subjects, docs/evaluation.md);
 *        the joint-position baseline leaves its coordinates plain.
 * @param frames frame feature vectors, all of one length, in time order
 * @param stamps their stamps (non-decreasing)
 * @param levels 1..4
 * @throws std::invalid_argument on no frames, sizes that differ, unsorted or non-finite stamps,
 *         levels outside 1..4, or Fourier coefficients outside 0..kMaxFourier
 */
Eigen::VectorXf temporalPyramid(const std::vector<Eigen::VectorXf>& frames, const std::vector<double>& stamps,
                                int levels, bool power = true, Pooling pooling = Pooling());

/** @brief Number of parts of a pyramid of @p levels levels: 2^levels - 1. */
int pyramidParts(int levels);

}  // namespace action_flow
