// The joint graph of a URDF, checked from its XML before urdfdom builds the tree.
#pragma once
#include <string>

class TiXmlElement;

namespace nmdp {

// The joints' graph from the XML, before urdfdom links the tree: urdfdom holds each link's
// children by shared pointer, so a cycle it is given is never freed, and one without a root
// makes it fail with no useful message. Each link has at most one parent joint, and following
// parents from any link reaches a link without one.
// Throws InputError naming `path`, the joint (and its line) or the links of a cycle.
void checkUrdfJointGraph(const TiXmlElement& robot, const std::string& path);

}  // namespace nmdp
