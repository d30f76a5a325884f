// <include file="..."/>: the elements of another file put in place of the element, as MuJoCo 2.2.2
// does before it reads a model (xml.cc): the included file's root element (of any tag; its
// attributes are ignored) is dropped and its child elements take the <include>'s place, in order,
// their own <include>s expanded in turn. Paths are relative to the folder of the main model file,
// also in a nested include (2.2.2 never changes that folder), and compiler/meshdir applies to the
// merged model as if it were one file. A file included twice (a cycle among them) is an error, as
// are an <include> with children and a file with nothing in its root.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "reader.hpp"

namespace lever::mjcf::detail {

/// Expand every <include> under `root`, the document of the model file `filename` (`bytes` long,
/// counted with the included files against Limits::kDocumentBytes). Each included element records
/// its file (Element::file), so that problems in it are reported there. Returns the included
/// files' paths, in the order read. Throws Problem.
std::vector<std::string> expand_includes(Element& root, const std::string& filename,
                                         std::size_t bytes);

}  // namespace lever::mjcf::detail
