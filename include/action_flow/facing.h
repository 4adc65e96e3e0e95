/**
 * @file facing.h
 * @brief Which way a person faces, from the shape of their trunk in one depth view, so that the
 *        descriptor grid can be turned with the person (orientation invariance, docs/tracker.md).
 *
 * The trunk's horizontal cross-section is wider than it is deep (shoulders about 0.36 m, chest
 * about 0.22 m for a 1.75 m person). The camera sees the near side of it: a flat arc when the
 * person faces the camera, a rounder one side on, skewed to one side in between. The estimate is
 * the turn of an ellipse of those proportions that fits the arc best: the points at chest height
 * (0.55 to 0.8 of the person's height) are laid on the ground plane, and for each turn the
 * ellipse's centre is fitted by Gauss-Newton with residuals capped (the arms, a hand in front);
 * a coarse search over turns is refined by a parabola through the best three.
 *
 * One view cannot tell front from back (an ellipse is the same turned by 180 degrees), so the
 * answer is always the one that faces the camera, in (-90, 90] degrees; a person facing away is
 * taken as facing the camera. Side on (near 90 degrees), left and right are ambiguous too.
 */
#pragma once

#include <action_flow/grid_descriptor.h>
#include <action_flow/types.h>

namespace action_flow
{
/**
 * @brief The person's facing relative to the way to the camera, in radians in (-pi/2, pi/2]:
 *        0 faces the camera, positive is turned towards the frame's +x (the person's left). NaN
 *        when fewer than 30 finite points lie at chest height.
 * @param person the person's points (any frame that @p where is in)
 * @param where the person's grid frame (ground, height, the view's axes)
 */
float facingFromTrunk(const Cloud& person, const PersonFrame& where);

}  // namespace action_flow
