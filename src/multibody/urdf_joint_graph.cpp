#include "multibody/urdf_joint_graph.hpp"

#include <tinyxml.h>

#include <map>
#include <set>
#include <utility>
#include <vector>

#include "common/input_error.hpp"

namespace nmdp {

namespace {

std::string jointElement(const std::string& joint) { return "<joint name=\"" + joint + "\">"; }

}  // namespace

void checkUrdfJointGraph(const TiXmlElement& robot, const std::string& file) {
  std::map<std::string, std::pair<std::string, std::string>> parent_of;  // child link → (parent link, joint)
  std::set<std::string> links;
  for (const TiXmlElement* l = robot.FirstChildElement("link"); l; l = l->NextSiblingElement("link"))
    if (const char* name = l->Attribute("name")) links.insert(name);
  for (const TiXmlElement* j = robot.FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const char* name = j->Attribute("name");
    const TiXmlElement* parent = j->FirstChildElement("parent");
    const TiXmlElement* child = j->FirstChildElement("child");
    const char* parent_link = parent ? parent->Attribute("link") : nullptr;
    const char* child_link = child ? child->Attribute("link") : nullptr;
    const std::string element = jointElement(name ? name : "?") + " (line " + std::to_string(j->Row()) + ")";
    if (!parent_link || !child_link) throw InputError(file + ": " + element + " needs <parent link=\"...\"/> and <child link=\"...\"/>");
    if (!links.count(parent_link)) throw InputError(file + ": " + element + ": parent link '" + parent_link + "' does not exist");
    if (!links.count(child_link)) throw InputError(file + ": " + element + ": child link '" + child_link + "' does not exist");
    if (std::string(parent_link) == child_link)
      throw InputError(file + ": " + element + ": its parent and child are the same link '" + child_link + "'");
    const auto [it, first] = parent_of.emplace(child_link, std::make_pair(std::string(parent_link), std::string(name ? name : "?")));
    if (!first)
      throw InputError(file + ": link '" + child_link + "' is the child of two joints, " + jointElement(it->second.second) + " and " +
                       jointElement(name ? name : "?") + ": a URDF is a tree (each link has at most one parent joint)");
  }
  // Links whose parents were followed to a root; every walk is bounded by the number of links.
  std::set<std::string> rooted;
  for (const std::string& start : links) {
    std::vector<std::string> path;
    std::string at = start;
    while (!rooted.count(at)) {
      auto up = parent_of.find(at);
      if (up == parent_of.end()) break;  // a root
      path.push_back(at);
      if (path.size() > links.size()) {  // more steps than links: `at` is on a cycle
        std::string cycle = "'" + at + "'";
        for (std::string c = parent_of[at].first; c != at; c = parent_of[c].first) cycle += " <- '" + c + "'";
        throw InputError(file + ": the joints form a cycle, " + cycle + " <- '" + at +
                         "' (child <- parent): a URDF is one tree with a root link");
      }
      at = up->second.first;
    }
    rooted.insert(path.begin(), path.end());
    rooted.insert(at);
  }
}

}  // namespace nmdp
