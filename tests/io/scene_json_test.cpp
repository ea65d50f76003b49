#include "hedra/io/scene_json.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include <unistd.h>

#include "hedra/io/text_reader.h"
#include "hedra/mesh/boolean.h"
#include "hedra/core/error.h"
#include "hedra/core/primitives.h"

namespace hedra {
namespace {

const std::string kExample = std::string(HEDRA_SOURCE_DIR) + "/examples/city-block.json";

void expect_same_body(const Body& a, const Body& b, const std::string& name) {
  EXPECT_EQ(a.vertices(), b.vertices()) << name;
  ASSERT_EQ(a.face_count(), b.face_count()) << name;
  for (int f = 0; f < a.face_count(); ++f) EXPECT_EQ(a.faces()[f].loops, b.faces()[f].loops) << name;
}

void expect_same_scene(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.bodies().size(), b.bodies().size());
  for (size_t i = 0; i < a.bodies().size(); ++i) {
    const SceneBody &x = a.bodies()[i], &y = b.bodies()[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.hidden, y.hidden) << x.name;
    EXPECT_EQ(x.material, y.material) << x.name;
    expect_same_body(x.body, y.body, x.name);
  }
  EXPECT_EQ(a.camera.projection, b.camera.projection);
  EXPECT_EQ(a.camera.eye, b.camera.eye);
  EXPECT_EQ(a.camera.target, b.camera.target);
  EXPECT_EQ(a.camera.direction, b.camera.direction);
  EXPECT_EQ(a.camera.fov_deg, b.camera.fov_deg);
  EXPECT_EQ(a.camera.width, b.camera.width);
  ASSERT_EQ(a.lights.size(), b.lights.size());
  for (size_t i = 0; i < a.lights.size(); ++i) {
    EXPECT_EQ(a.lights[i].type, b.lights[i].type);
    EXPECT_EQ(a.lights[i].direction, b.lights[i].direction);
    EXPECT_EQ(a.lights[i].position, b.lights[i].position);
    EXPECT_EQ(a.lights[i].intensity, b.lights[i].intensity);
  }
  EXPECT_EQ(a.image.background, b.image.background);
}

TEST(SceneJson, BuilderAndJsonGiveIdenticalScenes) {
  const std::string text = R"({
    "bodies": [
      {"name": "ground", "box": {"min": [0, 0, -1], "max": [100, 100, 0]}},
      {"name": "tower", "box": {"min": [0, 0, 0], "max": [2, 2, 10]},
       "transform": [{"rotate": {"axis": [0, 0, 1], "deg": 30}}, {"translate": [5, 0, 0]}],
       "material": {"color": [0.8, 0.3, 0.2], "ka": 0.2, "kd": 0.7, "ks": 0.2, "shininess": 20}},
      {"name": "a", "box": {"min": [20, 20, 0], "max": [24, 24, 4]}, "hidden": true},
      {"name": "b", "box": {"min": [22, 22, 2], "max": [26, 26, 6]}, "hidden": true},
      {"name": "cut", "subtract": ["a", "b"]},
      {"name": "ball", "sphere": {"center": [50, 50, 3], "radius": 3, "tolerance": 0.05}}
    ],
    "camera": {"projection": "perspective", "eye": [-30, -40, 25], "target": [20, 20, 0],
               "up": [0, 0, 1], "fov_deg": 40},
    "lights": [{"type": "sun", "latitude": 52.5, "longitude": 13.4, "time": "2026-06-21T10:00:00Z"}],
    "image": {"width": 640, "height": 480}
  })";
  Scene from_json = io::parse_scene("inline.json", text);

  Scene built;
  built.add("ground", box({0, 0, -1}, {100, 100, 0}));
  built.add("tower", box({0, 0, 0}, {2, 2, 10}).transformed(
                         Transform::rotation({0, 0, 1}, 30) * Transform::translation({5, 0, 0})))
      .with_color({0.8, 0.3, 0.2});
  built.add("a", box({20, 20, 0}, {24, 24, 4})).hide();
  built.add("b", box({22, 22, 2}, {26, 26, 6})).hide();
  built.add("cut", *subtract(built.get("a").body, built.get("b").body));
  built.add("ball", sphere({50, 50, 3}, 3, 0.05));
  built.camera = Camera::perspective({-30, -40, 25}, {20, 20, 0}, 40);
  built.camera.width = 640;
  built.camera.height = 480;
  built.lights.push_back(Light::sun(52.5, 13.4, UtcTime::parse("2026-06-21T10:00:00Z")));
  expect_same_scene(built, from_json);
  EXPECT_EQ(from_json.visible_bodies().size(), 4u);
}

TEST(SceneJson, EveryBodyTypeFromTheExample) {
  Scene s = io::read_scene(kExample);
  EXPECT_EQ(s.bodies().size(), 13u);
  EXPECT_EQ(s.get("ground").body.volume(), 35 * 30 * 1);
  EXPECT_EQ(s.get("L").body.face_count(), 8);
  EXPECT_NEAR(s.get("L").body.volume(), 12, 1e-12);
  EXPECT_EQ(s.get("plate").body.volume(), 12 - 2 * 2 * 0.5);
  EXPECT_NEAR(s.get("p").body.volume(), 2 * 2 * 3 / 6.0, 1e-12);
  EXPECT_EQ(s.get("cut").body.volume(), 6 * 6 * 4 - 4 * 4 * 2);
  EXPECT_TRUE(s.get("blockA").hidden);
  EXPECT_EQ(s.get("s").body.face_count(), 512);
  EXPECT_NE(s.get("tower").lod_note.find("pixel_tolerance 0.5 px"), std::string::npos);
  EXPECT_EQ(s.get("roof").body.face_count(), 5);
  EXPECT_NEAR(s.get("stump").body.volume(), 4.0 * 3 / 3 - (16.0 / 9) * 2 / 3, 1e-12);
  EXPECT_EQ(s.get("hex").body.face_count(), 8);
  EXPECT_EQ(s.camera.projection, Camera::Projection::Perspective);
  EXPECT_EQ(s.lights.size(), 4u);
  EXPECT_EQ(s.lights[0].type, Light::Type::Sun);
  EXPECT_GT(-s.lights[0].direction.z(), 0.5);  // the sun is high in June
  EXPECT_EQ(s.camera.width, 1024);
}

// The body types the example does not use: a mesh file (its path relative to the scene file,
// not to the working directory), unite and intersect of hidden operands.
TEST(SceneJson, MeshUniteAndIntersectBodies) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("hedra_scene_json_" + std::to_string(::getpid()));
  fs::create_directories(dir / "parts");
  std::ofstream(dir / "parts" / "cube.off")
      << "OFF\n8 6 0\n0 0 0\n2 0 0\n2 2 0\n0 2 0\n0 0 2\n2 0 2\n2 2 2\n0 2 2\n"
         "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
  std::ofstream(dir / "parts" / "scene.json") << R"({
    "bodies": [
      {"name": "part", "mesh": "cube.off", "transform": [{"translate": [10, 0, 0]}]},
      {"name": "a", "box": {"min": [0, 0, 0], "max": [2, 2, 2]}, "hidden": true},
      {"name": "b", "box": {"min": [1, 1, 1], "max": [3, 3, 3]}, "hidden": true},
      {"name": "u", "unite": ["a", "b"]},
      {"name": "i", "intersect": ["a", "b"]}
    ]})";
  const Scene s = io::read_scene((dir / "parts" / "scene.json").string());
  EXPECT_EQ(s.get("part").body.volume(), 8);
  EXPECT_EQ(s.get("part").body.bbox().min(), Vec3(10, 0, 0));
  EXPECT_EQ(s.get("u").body.volume(), 8 + 8 - 1);
  EXPECT_EQ(s.get("u").body.face_count(), 12);
  EXPECT_EQ(s.get("i").body.volume(), 1);
  EXPECT_EQ(s.get("i").body.face_count(), 6);
  EXPECT_EQ(s.visible_bodies().size(), 3u);
  fs::remove_all(dir);
}

// The top-level "tolerance" key imports meshes as `--tolerance` does; the reader's own
// tolerance (the command's option) wins over it.
TEST(SceneJson, ToleranceKeySnapsNearlyCoplanarMeshFaces) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("hedra_scene_tol_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  // A cube with its top as two triangles, one corner lifted by 1e-9: not coplanar exactly.
  std::ofstream(dir / "cube.off")
      << "OFF\n8 7 0\n0 0 0\n2 0 0\n2 2 0\n0 2 0\n0 0 2\n2 0 2\n2 2 2.000000001\n0 2 2\n"
         "4 0 3 2 1\n3 4 5 6\n3 4 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
  std::ofstream(dir / "exact.json") << R"({"bodies": [{"name": "c", "mesh": "cube.off"}]})";
  std::ofstream(dir / "loose.json")
      << R"({"tolerance": 1e-6, "bodies": [{"name": "c", "mesh": "cube.off"}]})";
  const Scene exact = io::read_scene((dir / "exact.json").string());
  EXPECT_EQ(exact.get("c").body.face_count(), 7);
  const Scene loose = io::read_scene((dir / "loose.json").string());
  EXPECT_EQ(loose.get("c").body.face_count(), 6);
  EXPECT_NEAR(loose.get("c").body.volume(), 8, 1e-8);
  EXPECT_EQ(io::read_scene((dir / "exact.json").string(), 1e-6).get("c").body.face_count(), 6);
  try {
    io::parse_scene("t.json", R"({"tolerance": -1, "bodies": [{"name": "b", "box": {"min": [0, 0, 0], "max": [1, 1, 1]}}]})");
    ADD_FAILURE() << "a negative tolerance was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("'tolerance' must be positive"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

TEST(SceneJson, WriteBackGivesAnEquivalentScene) {
  Scene s = io::read_scene(kExample);
  const std::string text = io::format_scene(s);
  Scene back = io::parse_scene("back.json", text);
  expect_same_scene(s, back);
  EXPECT_EQ(io::format_scene(back), text);  // a fixed point
}

struct ErrorCase {
  const char* text;
  const char* message;
};

TEST(SceneJson, ErrorsNameFileLineColumnAndProblem) {
  const ErrorCase cases[] = {
      {"{\"bodies\": [\n  {\"name\": \"L\",\n   \"prism\": {\"polygon\": [[0,0],[1,0]], \"z\": [0, 1]}}]}",
       "scene.json:3:25: body 'L': 'polygon' needs at least 3 points"},
      {"{\"bodies\": [{\"name\": \"a\", \"box\": {\"min\": [0,0,0], \"max\": [1,1,1]}, \"colour\": 1}]}",
       "scene.json:1:68: body 'a': unknown key 'colour' (expected name, one shape, transform, material, hidden)"},
      {"{\"bodies\": [], \"extra\": 1}",
       "scene.json:1:16: unknown key 'extra' (expected one of: version, tolerance, bodies, camera, lights, image)"},
      {"{\"bodies\": []}", "scene.json:1:12: 'bodies' is empty"},
      {"{\"bodies\": [{\"name\": \"a\", \"box\": {\"min\": [0,0,0], \"max\": [1,1]}}]}",
       "scene.json:1:58: body 'a': 'max' must be an array of 3 numbers"},
      {"{\"bodies\": [{\"name\": \"c\", \"subtract\": [\"x\", \"y\"]}]}",
       "scene.json:1:40: body 'c': operand 'x' is not a body defined earlier in the list"},
      {"{\"bodies\": [{\"name\": \"a\", \"box\": {\"min\": [0,0,0], \"max\": [1,1,1]}},\n"
       "             {\"name\": \"a\", \"box\": {\"min\": [0,0,0], \"max\": [1,1,1]}}]}",
       "scene.json:2:23: body name 'a' is used twice"},
      {"{\"bodies\": [{\"name\": \"a\", \"box\": {\"min\": [0,0,0], \"max\": [1,1,1]}}],\n"
       " \"lights\": [{\"type\": \"sun\", \"latitude\": 52.5, \"longitude\": 13.4, \"time\": \"2026-06-21T23:00:00Z\"}]}",
       "scene.json:2:13: the sun is below the horizon at latitude 52.5, longitude 13.4"},
      {"{\"bodies\": [{\"name\": \"a\", \"box\": {\"min\": [0,0,0], \"max\": [0,1,1]}}]}",
       "scene.json:1:34: body 'a': box: min must be below max in every coordinate"},
      {"{\"bodies\": [{\"name\": \"a\", \"box\": {\"min\": [0,0,0], \"max\": [1,1,1]}}],\n \"camera\": {\"projection\": \"fisheye\"}}",
       "scene.json:2:27: 'projection' must be \"parallel\" or \"perspective\""},
      {"{\"bodies\": [{\"name\": \"s\", \"sphere\": {\"center\": [0,0,0], \"radius\": 1}}]}",
       "scene.json:1:37: body 's': missing 'tolerance' or 'pixel_tolerance'"},
      {"{\"bodies\": [1,]}", "scene.json:1:15: unexpected character ']'"},
      {"{\"bodies\": [{\"name\": \"m\", \"mesh\": \"missing.off\"}]}", "missing.off: cannot open"},
      {"", "scene.json:1:1: empty file (expected a JSON value)"},
  };
  for (const ErrorCase& c : cases) {
    try {
      io::parse_scene("scene.json", c.text);
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos)
          << "got:      " << e.what() << "\nexpected: " << c.message;
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
  }
}

TEST(SceneJson, RandomlyDamagedFilesNeverCrash) {
  const std::string good = io::read_file(kExample);
  std::mt19937 random(7);
  int accepted = 0, rejected = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::string text = good;
    const int edits = 1 + static_cast<int>(random() % 4);
    for (int e = 0; e < edits; ++e) {
      const size_t at = random() % text.size();
      switch (random() % 4) {
        case 0: text.erase(at, 1 + random() % 8); break;
        case 1: text.insert(at, 1, "{}[],:\"0-e9x.\\ "[random() % 15]); break;
        case 2: text[at] = static_cast<char>(random() % 256); break;
        case 3: text.insert(at, text.substr(random() % text.size(), random() % 20)); break;
      }
      if (text.empty()) text = "{";
    }
    try {
      io::parse_scene(kExample, text);
      ++accepted;
    } catch (const InvalidInput&) {
      ++rejected;
    } catch (const IoError&) {
      ++rejected;
    }
  }
  EXPECT_EQ(accepted + rejected, 300);
  EXPECT_GT(rejected, 200);
}

}  // namespace
}  // namespace hedra

namespace hedra {
namespace {

// An open surface (a roof of two slopes and a flat pentagon, inline) written by format_scene
// comes back as the same open surface: the same two-sided body, polygons and areas (it was
// written as a closed flat polyhedron of both faces of each polygon, which no reader accepts).
TEST(SceneJson, OpenSurfacesAreWrittenBackAsOpenSurfaces) {
  const std::string text = R"({"version": 1, "bodies": [
    {"name": "roof", "polyhedron": {"vertices": [[0,0,0],[2,0,0],[2,2,1],[0,2,1],[2,4,0],[0,4,0]],
                                    "faces": [[0,1,2,3],[3,2,4,5]]}},
    {"name": "block", "polyhedron": {"vertices": [[0,0,-2],[1,0,-2],[1,1,-2],[0,1,-2],[0,0,-1],[1,0,-1],[1,1,-1],[0,1,-1]],
                                     "faces": [[0,3,2,1],[4,5,6,7],[0,1,5,4],[1,2,6,5],[2,3,7,6],[3,0,4,7]]}}]})";
  const Scene a = io::parse_scene("roof.json", text);
  ASSERT_EQ(a.surfaces.size(), 1u);
  ASSERT_EQ(a.bodies().size(), 2u);  // roof (one two-sided surface of 2 faces), block
  EXPECT_EQ(a.bodies()[0].name, "roof");
  EXPECT_EQ(a.bodies()[0].body.face_count(), 4);
  const Scene b = io::parse_scene("again.json", io::format_scene(a));
  ASSERT_EQ(b.surfaces.size(), 1u);
  EXPECT_EQ(b.surfaces[0].name, "roof");
  EXPECT_EQ(b.surfaces[0].faces, a.surfaces[0].faces);
  EXPECT_EQ(b.surfaces[0].boundary_edges, a.surfaces[0].boundary_edges);
  EXPECT_DOUBLE_EQ(b.surfaces[0].area, a.surfaces[0].area);
  ASSERT_EQ(b.bodies().size(), a.bodies().size());
  for (size_t i = 0; i < a.bodies().size(); ++i) {
    EXPECT_EQ(b.bodies()[i].name, a.bodies()[i].name);
    EXPECT_EQ(b.bodies()[i].body.two_sided(), a.bodies()[i].body.two_sided());
    EXPECT_EQ(b.bodies()[i].body.vertices(), a.bodies()[i].body.vertices());
    EXPECT_EQ(b.bodies()[i].body.face_count(), a.bodies()[i].body.face_count());
  }
}

}  // namespace
}  // namespace hedra

#include <nlohmann/json.hpp>

#include "hedra/io/report_json.h"
#include "hedra/visibility/shadows.h"

namespace hedra {
namespace {

// shadows_json builds each face's object apart and splices the face arrays in at a marker:
// a body named like the marker, two lights, and the document must still be the one DOM dump.
TEST(ReportJson, ShadowFacesSplicedIntoTheDocumentAsOneDump) {
  const Scene scene = io::parse_scene("s.json", R"({"version": 1, "bodies": [
    {"name": "ground", "box": {"min": [-5, -5, -1], "max": [5, 5, 0]}},
    {"name": "hedra-faces-of-light-0-a93f0c", "box": {"min": [0, 0, 0], "max": [1, 1, 1]}}],
    "lights": [{"type": "point", "position": [3, 2, 6]}, {"type": "directional", "direction": [1, 0.5, -1]}]})");
  const ShadowResult result = compute_shadows(scene);
  const std::string text = io::shadows_json(scene, "s.json", result, false, 1.5);
  const nlohmann::json doc = nlohmann::json::parse(text);
  ASSERT_EQ(doc["lights"].size(), 2u);
  for (const auto& light : doc["lights"]) EXPECT_EQ(light["faces"].size(), 12u);
  EXPECT_EQ(doc["lights"][1]["faces"][11]["body"], "hedra-faces-of-light-0-a93f0c");
  // Re-dumped from the parsed DOM, the same bytes (sorted keys, no spaces).
  EXPECT_EQ(doc.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), text);
  double ground = 0;
  for (const auto& f : doc["lights"][0]["faces"])
    if (f["body"] == "ground" && f["face"] == 5 && !f["self_shadowed"].get<bool>()) ground += f["shadow_area"].get<double>();
  EXPECT_GT(ground, 1.0);
}

// write_shadows_json hands the document over a wave of face blocks at a time (64 blocks of
// 1024 faces): a sphere of 70 688 faces crosses a wave's end, and the pieces must join into the
// one DOM dump that shadows_json gives, every face once and in order.
// The waves of write_shadows_json (1024 faces a block, 64 blocks a wave) on a scene of more
// than one wave: about 20 s under the sanitizers, so Release only; the small waves below run
// the same code in both builds.
#ifndef HEDRA_SANITIZED
TEST(ReportJson, ShadowFacesWrittenInWavesJoinIntoTheOneDump) {
  const Scene scene = io::parse_scene("s.json", R"({"version": 1, "bodies": [
    {"name": "s", "sphere": {"center": [0, 0, 1.2], "radius": 1, "tolerance": 7e-5}}],
    "lights": [{"type": "point", "position": [3, 2, 6]}]})");
  const int faces = scene.bodies()[0].body.face_count();
  ASSERT_GT(faces, 64 * 1024);
  const ShadowResult result = compute_shadows(scene);
  std::string joined;
  int pieces = 0;
  io::write_shadows_json([&](std::string_view s) { joined += s, ++pieces; }, scene, "s.json", result, false, 2.5);
  EXPECT_GE(pieces, 70);  // 70 blocks of faces, and the document's parts around them
  EXPECT_EQ(joined, io::shadows_json(scene, "s.json", result, false, 2.5));
  const nlohmann::json doc = nlohmann::json::parse(joined);
  const auto& list = doc["lights"][0]["faces"];
  ASSERT_EQ(list.size(), static_cast<size_t>(faces));
  for (int f = 0; f < faces; ++f) ASSERT_EQ(list[static_cast<size_t>(f)]["face"], f);
  EXPECT_EQ(doc.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), joined);
}
#endif

TEST(ReportJson, SmallWavesGiveTheSameBytes) {
  const Scene scene = io::parse_scene("s.json", R"({"version": 1, "bodies": [
    {"name": "g", "box": {"min": [-3, -3, -0.5], "max": [3, 3, 0]}},
    {"name": "s", "sphere": {"center": [0, 0, 1.2], "radius": 1, "tolerance": 1e-2}}],
    "lights": [{"type": "point", "position": [3, 2, 6]}, {"type": "directional", "direction": [-1, -2, -3]}]})");
  const int faces = scene.bodies()[0].body.face_count() + scene.bodies()[1].body.face_count();
  ASSERT_GT(faces, 7 * 5 * 3);  // more than three waves of 5 blocks of 7 faces
  ShadowOptions options;
  options.visible_parts = true;
  const ShadowResult result = compute_shadows(scene, options);
  const std::string whole = io::shadows_json(scene, "s.json", result, true, 2.5);
  for (const auto& [block, wave] : {std::pair<size_t, size_t>{7, 5}, {1, 1}, {1000, 3}}) {
    std::string joined;
    int pieces = 0;
    io::internal::write_shadows_json_in_waves([&](std::string_view s) { joined += s, ++pieces; },
                                              scene, "s.json", result, true, 2.5, block, wave);
    EXPECT_EQ(joined, whole) << block << " faces a block, " << wave << " blocks a wave";
    // Per light: its blocks, and the document's parts around them.
    EXPECT_GE(pieces, 2 * ((faces + static_cast<int>(block) - 1) / static_cast<int>(block))) << block;
  }
  const nlohmann::json doc = nlohmann::json::parse(whole);
  ASSERT_EQ(doc["lights"].size(), 2u);
  ASSERT_EQ(doc["lights"][1]["faces"].size(), static_cast<size_t>(faces));
  EXPECT_THROW(io::internal::write_shadows_json_in_waves([](std::string_view) {}, scene, "s.json",
                                                         result, true, 2.5, 0, 1),
               std::invalid_argument);
}

}  // namespace
}  // namespace hedra
