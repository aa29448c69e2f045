// `ifem_bench`: the benchmark program behind BENCHMARKS.md. Each section is a function in its
// bench_<name>.cpp, listed below. Figures are medians over --repeat runs (default 5).
//
//   ifem_bench SECTION [--repeat N] [section options]
#include <cstdio>
#include <cstring>
#include <string>

namespace ifem::bench {
// Each returns a process exit code; argv[0] is the section name.
int foundation(int argc, char** argv);
int solvers(int argc, char** argv);
int eigen(int argc, char** argv);
int pointcloud(int argc, char** argv);
int refine(int argc, char** argv);
int geodesic(int argc, char** argv);
int curves(int argc, char** argv);
int vector_heat(int argc, char** argv);
int batch(int argc, char** argv);
int query(int argc, char** argv);
int field(int argc, char** argv);
int small(int argc, char** argv);
int vector_repeat(int argc, char** argv);
int isolines(int argc, char** argv);
int trace(int argc, char** argv);
int integer(int argc, char** argv);
int simplify(int argc, char** argv);
int integer_crosscheck(int argc, char** argv);
int transfer(int argc, char** argv);
}  // namespace ifem::bench

namespace {

struct Section {
  const char* name;
  const char* summary;
  int (*run)(int, char**);
};

const Section kSections[] = {
    {"foundation", "load, build, mollify, flip to IDT, assemble L + M on 10k..1M+ faces",
     ifem::bench::foundation},
    {"pointcloud",
     "tufted-cover Laplacian on nonmanifold/big meshes; point clouds 10k..1M, per stage",
     ifem::bench::pointcloud},
    {"refine", "intrinsic Delaunay refinement: rocketship, needle uv sphere, igea",
     ifem::bench::refine},
    {"geodesic",
     "FlipOut paths, single-source geodesics, Bézier curves on icospheres 10k..1M faces",
     ifem::bench::geodesic},
    {"curves",
     "curves as constrained edges: insertion, constrained refinement, curve_poisson and "
     "curve_distance against the unconstrained solves, icospheres 10k..1M faces",
     ifem::bench::curves},
    {"solvers", "heat distance precompute + query 10k..1M faces; k = 10, 50 eigenpairs",
     ifem::bench::solvers},
    {"eigen",
     "k = 10, 50 eigenpairs on a 100k-face sphere, 1 and default threads, factorization alone; "
     "--write DIR: L and M as Matrix Market",
     ifem::bench::eigen},
    {"vector_heat",
     "vector heat precompute, transport, extension, log map vs scalar heat 10k..1M faces; "
     "complex factorization choices; --log-map-mesh F[,F...]: the two log-map methods "
     "(affine, vector heat) on mesh files instead",
     ifem::bench::vector_heat},
    {"batch", "heat distances from k = 1, 8, 32, 128 sources at once vs one query per source",
     ifem::bench::batch},
    {"query",
     "heat queries on icosphere(--n 224) or --mesh FILE, --sources K at once (--repeat 21 "
     "[--mixed] [--kept: into a matrix kept between calls]), for profilers",
     ifem::bench::query},
    {"field",
     "smoothest and aligned direction fields, n = 1 and 4, 10k..1M faces, rocketship, igea",
     ifem::bench::field},
    {"small",
     "one mesh in a fresh process: first and median L + M or heat precompute (compare "
     "OMP_NUM_THREADS=1 against the default: scripts/bench_small.sh)",
     ifem::bench::small},
    {"vector_repeat",
     "repeated transport, log map (solver and recipe) and a smoothest 4-field against one scalar "
     "heat query, interleaved, on icosphere(--n 23) or --mesh FILE; --what memory: peak RSS",
     ifem::bench::vector_repeat},
    {"isolines",
     "isolines of a heat distance (--levels 10) vs the heat query that made it, icospheres "
     "10k..1M faces (--max-n 224)",
     ifem::bench::isolines},
    {"trace",
     "straight geodesics (ifem trace): 1000 rays as long as the diameter on a 100k-face "
     "icosphere and the armadillo; time per ray and per side crossed",
     ifem::bench::trace},
    {"integer",
     "flips to Delaunay with normal coordinates vs signposts (interleaved), tracing every edge "
     "with each: rocketship, igea (--mesh F[,F...])",
     ifem::bench::integer},
    {"simplify",
     "intrinsic simplification of icospheres 10k..1M faces to --vertices (10,000): removals "
     "per second, flips per removal, the prolongation's assembly",
     ifem::bench::simplify},
    {"integer-crosscheck",
     "Delaunay refinement (25°, 30°) with signposts and integer coordinates on every mesh of a "
     "directory (default ../shared/data/meshes; --generated: also the adversarial generators): "
     "success, time, agreement, area partition, as a markdown table",
     ifem::bench::integer_crosscheck},
    {"transfer",
     "point location both ways (100k points) and L2 function transfer after refinement to 25°, "
     "integer coordinates vs signposts (interleaved): igea (--mesh F)",
     ifem::bench::transfer},
};

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2) {
    for (const Section& s : kSections) {
      if (std::strcmp(argv[1], s.name) == 0) return s.run(argc - 1, argv + 1);
    }
  }
  std::printf("usage: ifem_bench SECTION [options]\n\nsections:\n");
  for (const Section& s : kSections) std::printf("  %-12s %s\n", s.name, s.summary);
  return argc >= 2 && std::strcmp(argv[1], "--help") == 0 ? 0 : 2;
}
