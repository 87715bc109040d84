// The scenes stand without the command line above them: this test links
// fretsim_scenes alone, so a scene that calls into src/app's commands or CLI
// fails to link here.
#include <fretsim/scenes/scene.h>

#include <gtest/gtest.h>

using namespace fretsim;

TEST(SceneLayer, EveryDeclaredParameterHasHelpText)
{
  for (const auto &name : scenes::scene_names())
    {
      // Held here: specs() refers into the parameters, which must outlive the loop.
      const auto parameters = scenes::declare_parameters(name);
      for (const auto &spec : parameters.specs())
        EXPECT_FALSE(spec.doc.empty()) << name << ": " << spec.path;
    }
}

TEST(SceneLayer, AMissingConfigurationIsAnInputError)
{
  EXPECT_THROW(scenes::load_scene("no-such-configuration.prm"), app::InputError);
}
