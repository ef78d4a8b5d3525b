// `pbs view` in a real browser: headless Chromium, driven through chromedriver, opens the page, orbits by
// dragging, flies with the keys, moves a slider, switches to the FLIP map and goes to a path's view; after
// each, the frame the page shows must be the one `pbs render` makes for the page's camera. Skips where
// Chromium or chromedriver is absent (the README's test command installs both).
#include "viewed_groups.hpp"
#include "webdriver.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstdlib>
#include <regex>

namespace pbs::test {
namespace {

// The groups scene's view, and a browser to look at it with.
struct BrowserView : ViewedGroups {
  Browser browser{900, 500};

  // Waits for the page's still view to be fully refined, then returns what it shows.
  nlohmann::json refined() {
    EXPECT_TRUE(browser.waitFor("window.pbsView && window.pbsView.refined", 60.0))
        << "the page did not finish refining; errors: " << browser.run("return window.pbsView.errors;").dump();
    return browser.run("return window.pbsView.shown;");
  }
  // The shown frame's query asked again (as another client, so that it is not dropped as superseded).
  std::string fetchShown(const nlohmann::json& shown) {
    const std::string query =
        std::regex_replace(shown["query"].get<std::string>(), std::regex("client=[^&]*"), "client=check");
    const auto frame = client.Get("/api/frame?" + query);
    EXPECT_TRUE(frame && frame->status == 200);
    return frame ? frame->body : "";
  }
  // What `pbs render` writes for the page's camera (when its target is the scene's centre) and settings, the
  // server's `--rays-cheaper keep --geometry raster` included.
  std::string rendered(const std::string& more) {
    const nlohmann::json camera = browser.run("return window.pbsView.camera();");
    const std::filesystem::path file = scratch / "rendered.png";
    const CommandResult render =
        runPbs("render " + quoted(scene) + " --surfels " + quoted(surfels) +
               " --rays-cheaper keep --geometry raster --size 320x180 --orbit " + exactDecimal(camera["az"]) + "," +
               exactDecimal(camera["el"]) + "," + exactDecimal(camera["dist"]) + more + " -o " + quoted(file));
    EXPECT_EQ(render.status, 0) << render.err;
    return readFile(file);
  }
};

TEST(ViewBrowser, DraggingTogglingAndSlidingChangeTheFramesAsPbsRenderWould) {
  PBS_REQUIRE_CHROMIUM();
  BrowserView view;
  ASSERT_GT(view.server.port, 0);
  ASSERT_TRUE(view.browser.started()) << "chromedriver did not start a headless Chromium session";
  const std::string url = "http://127.0.0.1:" + std::to_string(view.server.port) + "/?size=320x180";

  // Opened, the page refines its still view to 16 rays a pixel.
  view.browser.open(url);
  nlohmann::json shown = view.refined();
  EXPECT_EQ(shown["stats"]["drawn_by"], "embree");
  EXPECT_EQ(shown["stats"]["samples"], 16);
  EXPECT_TRUE(view.fetchShown(shown) == view.rendered(" --mode embree --samples 16"));

  // Refinement off: the still view is the surfel frame, pbs render's default view at the same size.
  view.browser.click("#refine");
  shown = view.refined();
  EXPECT_EQ(shown["stats"]["drawn_by"], "surfels");
  const std::string first = view.fetchShown(shown);
  EXPECT_TRUE(first == view.rendered(""));

  // Dragging orbits: 120 pixels to the right turn the azimuth by 48 degrees.
  const double azimuth = view.browser.run("return window.pbsView.camera().az;").get<double>();
  view.browser.drag("#stage", 120, 0, 6);
  shown = view.refined();
  const nlohmann::json camera = view.browser.run("return window.pbsView.camera();");
  EXPECT_NEAR(camera["az"].get<double>(), azimuth + 48.0, 1e-9);
  const std::string orbited = view.fetchShown(shown);
  EXPECT_TRUE(orbited != first);
  EXPECT_TRUE(orbited == view.rendered(""));

  // A slider: the overdraw, moved down with the keyboard, changes which nodes draw surfels (arrays that
  // ran out at 16 suffice at less, so fewer nodes are descended into).
  const double surfelsBefore = shown["stats"]["surfels"].get<double>();
  view.browser.click("#overdraw");
  view.browser.type({kArrowLeft, kArrowLeft, kArrowLeft, kArrowLeft, kArrowLeft, kArrowLeft, kArrowLeft, kArrowLeft});
  shown = view.refined();
  const double overdraw =
      view.browser.run("return Number(new URLSearchParams(window.pbsView.shown.query).get('overdraw'));").get<double>();
  EXPECT_LT(overdraw, 16.0);
  EXPECT_NE(shown["stats"]["surfels"].get<double>(), surfelsBefore);
  EXPECT_TRUE(view.fetchShown(shown) == view.rendered(" --overdraw " + exactDecimal(overdraw)));

  // The FLIP map: a comparison against 16 rays a pixel, with its error.
  view.browser.click("input[name=show][value=flip]");
  shown = view.refined();
  EXPECT_GT(shown["stats"]["flip"].get<double>(), 0.0);
  EXPECT_TRUE(view.fetchShown(shown) != orbited);

  // Flying: W moves the camera's target along the view.
  view.browser.click("input[name=show][value=surfels]");
  view.refined();
  const nlohmann::json before = view.browser.run("return window.pbsView.camera();");
  view.browser.click("#stage");
  view.browser.type({"w", "w", "w"});
  shown = view.refined();
  const nlohmann::json after = view.browser.run("return window.pbsView.camera();");
  EXPECT_NE(after["tx"], before["tx"]);
  EXPECT_EQ(after["az"], before["az"]);

  // Go to: the approach's first stop.
  view.browser.click("#path option:nth-child(2)");
  shown = view.refined();
  const nlohmann::json stop = view.browser.run("return window.pbsView.camera();");
  EXPECT_LT(stop["dist"].get<double>(), 10.0);
  EXPECT_NE(stop["tx"], after["tx"]);

  // The overlays: node boxes drawn over the frame, and each pixel tinted by what drew it.
  view.browser.click("#boxes");
  view.refined();
  EXPECT_TRUE(view.browser.waitFor(
      "(() => { const c = document.getElementById('overlay'); const d = c.getContext('2d').getImageData(0, 0, "
      "c.width, c.height).data; for (let i = 3; i < d.length; i += 4) if (d[i]) return true; return false; })()",
      30.0))
      << "no node box was drawn";
  view.browser.click("input[name=show][value=source]");
  shown = view.refined();
  EXPECT_EQ(shown["query"].get<std::string>().find("show=source") != std::string::npos, true);
  EXPECT_TRUE(view.fetchShown(shown) != view.rendered(""));

  // A click picks the node under it: its panel, its ρ(k) curve and capture views; the prefix slider then
  // draws its first k surfels alone.
  view.browser.click("input[name=show][value=surfels]");
  view.refined();
  const nlohmann::json hit = view.browser.run(
      "const f = document.getElementById('frame'); const c = document.createElement('canvas'); c.width = "
      "f.naturalWidth;"
      "c.height = f.naturalHeight; const g = c.getContext('2d'); g.drawImage(f, 0, 0);"
      "const d = g.getImageData(0, 0, c.width, c.height).data;"
      "for (let i = 0; i < d.length; i += 4) if (d[i + 3] === 255) return [(i / 4) % c.width, Math.floor(i / 4 / "
      "c.width)];"
      "return null;");
  ASSERT_TRUE(hit.is_array()) << "the frame covers no pixel";
  view.browser.clickAt("#frame", hit[0].get<int>(), hit[1].get<int>());
  ASSERT_TRUE(view.browser.waitFor("window.pbsView.node && !document.getElementById('node-panel').hidden", 30.0));
  const nlohmann::json picked = view.browser.run("return window.pbsView.node;");
  EXPECT_TRUE(picked.contains("path"));
  // The groups' leaves are drawn from their own arrays at this size.
  ASSERT_TRUE(picked.contains("array")) << picked.dump();
  EXPECT_TRUE(view.browser.waitFor("document.querySelector('#rho polyline')", 30.0));
  EXPECT_TRUE(view.browser.waitFor("document.getElementById('node-views').naturalWidth > 0", 30.0));
  view.browser.click("#prefix");
  shown = view.refined();
  const std::string query = shown["query"].get<std::string>();
  EXPECT_NE(query.find("show=prefix"), std::string::npos);
  EXPECT_NE(query.find("node=" + std::to_string(picked["node"].get<int>())), std::string::npos);
  const double prefix = view.browser.run("return window.pbsView.shownPrefix();").get<double>();
  EXPECT_EQ(shown["stats"]["surfels"].get<double>(), prefix);
  view.browser.type({kArrowLeft, kArrowLeft, kArrowLeft});
  const nlohmann::json fewer = view.refined();
  EXPECT_LT(fewer["stats"]["surfels"].get<double>(), prefix);

  // Moving surfel frames draw less of the overdraw while they are slow, never less than the server takes (on
  // a loaded machine 1/16 of a low setting was refused: "overdraw: expected a number in [0.25, 256]").
  const double least = view.browser
                           .run(
                               "const saved = [view.lod.overdraw, view.movingScale];"
                               "view.lod.overdraw = 0.5; view.movingScale = 1 / 16;"
                               "const least = movingOverdraw();"
                               "[view.lod.overdraw, view.movingScale] = saved;"
                               "return least;")
                           .get<double>();
  EXPECT_EQ(least, 0.25);

  if (const char* folder = std::getenv("PBS_VIEW_SCREENSHOT")) writeFile(folder, view.browser.screenshot());
  const std::string screenshot = view.browser.screenshot();
  EXPECT_EQ(screenshot.substr(1, 3), "PNG");
  const nlohmann::json pageErrors = view.browser.run("return window.pbsView.errors;");
  EXPECT_TRUE(pageErrors.empty()) << pageErrors.dump();

  const std::optional<int> status = view.server.process.stop(SIGINT, 30.0);
  ASSERT_TRUE(status);
  EXPECT_EQ(*status, 0);
}

TEST(ViewBrowser, WithoutSurfelsThePageShowsTheSceneExactlyAndMakesThem) {
  PBS_REQUIRE_CHROMIUM();
  ScratchDir scratch;
  groupsFile(scratch);
  ViewServer server({"view", (scratch / "groups.glb").string()});
  ASSERT_GT(server.port, 0);
  Browser browser(900, 500);
  ASSERT_TRUE(browser.started());
  browser.open("http://127.0.0.1:" + std::to_string(server.port) + "/?size=320x180&refine=0");
  ASSERT_TRUE(browser.waitFor("window.pbsView && window.pbsView.refined", 60.0));
  EXPECT_EQ(browser.run("return window.pbsView.shown.stats.drawn_by;"), "embree");
  EXPECT_EQ(browser.run("return document.querySelector('input[value=surfels]').disabled;"), true);
  browser.click("#make-surfels-button");
  ASSERT_TRUE(browser.waitFor("window.pbsView.surfelsMade && window.pbsView.refined", 120.0))
      << browser.run("return document.getElementById('make-surfels-progress').textContent;").dump();
  EXPECT_EQ(browser.run("return window.pbsView.shown.stats.drawn_by;"), "surfels");
  EXPECT_NE(browser.run("return document.getElementById('make-surfels-progress').textContent;")
                .get<std::string>()
                .find("made in"),
            std::string::npos);
}

}  // namespace
}  // namespace pbs::test
