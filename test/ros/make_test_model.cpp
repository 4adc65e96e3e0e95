// Writes the tiny models the classifier rostests load, through the core's ActionModel::save:
//   <dir>/two_actions.afm   "raise": every frame descriptor is e_0; "push": every frame is e_1
//   <dir>/corrupt.afm       the same file with one byte of its payload flipped
//   <dir>/posture_flow.afm  the default recognizer, "still" (no flow) against "moving" (flow everywhere)
// A query whose frames are all e_0 is at distance 0 from "raise" and sqrt(2 F) from "push".
#include <action_flow/action_model.h>

#include <cstdio>
#include <fstream>
#include <iterator>

int main(int argc, char** argv)
{
  if (argc != 2)
  {
    std::fprintf(stderr, "usage: make_test_model OUTPUT_DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  try
  {
    action_flow::ActionModel model;
    const int per_frame = 3 * model.params.grid.cells();
    const int frames = model.params.frames;
    model.descriptors = Eigen::MatrixXf::Zero(2, per_frame * frames);
    for (int f = 0; f < frames; ++f)
    {
      model.descriptors(0, f * per_frame + 0) = 1.0f;
      model.descriptors(1, f * per_frame + 1) = 1.0f;
    }
    model.labels = { "raise", "push" };
    model.persons = { "a", "a" };
    model.save(dir + "/two_actions.afm");

    std::ifstream in(dir + "/two_actions.afm", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    bytes[bytes.size() - 10] ^= 0x5a;
    std::ofstream(dir + "/corrupt.afm", std::ios::binary) << bytes;

    action_flow::ActionModel pf;
    pf.params = action_flow::defaultRecognitionParams();
    pf.params.pyramid.c = 1.0;
    pf.params.pyramid.flow = action_flow::FlowEncoding::Bins;
    pf.params.pyramid.mirror = action_flow::MirrorMode::Off;
    pf.descriptors = Eigen::MatrixXf::Zero(2, pf.sequenceLength());
    pf.descriptors.row(1).setConstant(1.0f);
    pf.labels = { "still", "moving" };
    pf.persons = { "a", "a" };
    pf.linear = action_flow::LinearClassifier::train(pf.descriptors, pf.labels, pf.params.pyramid.c);
    pf.save(dir + "/posture_flow.afm");
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "make_test_model: %s\n", e.what());
    return 1;
  }
  return 0;
}
