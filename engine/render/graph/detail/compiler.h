#pragma once
// Internal: RenderGraph::compile() as a list of short, named steps (compile.cpp, barriers.cpp).
#include <vector>

#include "engine/render/graph/detail/graph_data.h"
#include "engine/render/graph/render_graph.h"

namespace cumulo::render::detail {

class Compiler {
 public:
  Compiler(VkExtent2D output_size, const std::vector<ResourceDecl>& resources, const std::vector<PassDecl>& passes,
           const CompileOptions& options)
      : output_size_(output_size), resources_(resources), passes_(passes), options_(options) {}

  CompiledGraph run() {
    validate();
    merge_accesses();
    describe_resources();
    cull();
    order();
    compute_lifetimes();
    assign_memory();
    derive_barriers();
    return std::move(out_);
  }

 private:
  void validate();            // versions, usages vs resource kinds and queues, names, descs
  void merge_accesses();      // one ResourceAccess per (pass, resource); one layout per image per pass
  void describe_resources();  // resolve relative sizes, creation usage flags
  void cull();                // walk back from the imported (output) resources; dead passes are culled
  void order();               // execution order of the live passes
  void compute_lifetimes();   // first/last use of every resource
  void assign_memory();       // alias transient images with non-overlapping lifetimes
  void derive_barriers();     // every barrier and layout transition, per pass and at the end

  [[noreturn]] void fail_pass(uint32_t pass, const char* what, uint32_t resource) const;

  VkExtent2D output_size_;
  const std::vector<ResourceDecl>& resources_;
  const std::vector<PassDecl>& passes_;
  const CompileOptions& options_;

  std::vector<std::vector<ResourceAccess>> accesses_;  // per declared pass, merged
  std::vector<bool> live_;                             // per declared pass
  std::vector<uint32_t> order_;                        // declared indices of live passes, execution order
  CompiledGraph out_;
};

}  // namespace cumulo::render::detail
