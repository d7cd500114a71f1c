#pragma once
/// \file
/// A per-call hint telling a backend how coherent a packet's rays are. Backends that cannot use
/// it (reference, SaarCOR) accept and ignore it; the result never depends on it.

namespace igi {

/// How alike the rays of one packet are: neighbouring pixels and shadow rays to one point are
/// coherent; diffuse bounces are not.
enum class Coherence { coherent, incoherent };

}  // namespace igi
