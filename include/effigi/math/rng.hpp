#pragma once
// PCG32 (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient Statistically
// Good Algorithms for Random Number Generation"): 64-bit state, 32-bit output.
#include <cstdint>

namespace effigi {

class PCG32 {
public:
    PCG32() { seed(0x853c49e6748fea9bull, 0xda3e39cb94b95bdbull); }
    PCG32(std::uint64_t initState, std::uint64_t initSeq) { seed(initState, initSeq); }

    void seed(std::uint64_t initState, std::uint64_t initSeq = 1) {
        m_state = 0;
        m_inc = (initSeq << 1u) | 1u;
        nextUInt();
        m_state += initState;
        nextUInt();
    }

    std::uint32_t nextUInt() {
        std::uint64_t old = m_state;
        m_state = old * 6364136223846793005ull + m_inc;
        auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
        auto rot = static_cast<std::uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
    }

    /// Uniform float in [0, 1): the top 24 bits scaled exactly.
    float nextFloat() { return static_cast<float>(nextUInt() >> 8) * 0x1p-24f; }
    double nextDouble() {
        std::uint64_t hi = nextUInt(), lo = nextUInt();
        return static_cast<double>(((hi << 32) | lo) >> 11) * 0x1p-53;
    }

    /// Jump ahead or back by delta steps in O(log delta) (Brown 1994).
    void advance(std::int64_t delta);

private:
    std::uint64_t m_state = 0, m_inc = 0;
};

inline void PCG32::advance(std::int64_t delta_) {
    std::uint64_t curMult = 6364136223846793005ull, curPlus = m_inc, accMult = 1u, accPlus = 0u;
    auto delta = static_cast<std::uint64_t>(delta_);
    while (delta > 0) {
        if (delta & 1) {
            accMult *= curMult;
            accPlus = accPlus * curMult + curPlus;
        }
        curPlus = (curMult + 1) * curPlus;
        curMult *= curMult;
        delta /= 2;
    }
    m_state = accMult * m_state + accPlus;
}

/// 64-bit mix (MurmurHash3 finaliser): decorrelates seeds built from pixel coordinates.
inline std::uint64_t mixBits(std::uint64_t v) {
    v ^= v >> 31;
    v *= 0x7fb5d329728ea185ull;
    v ^= v >> 27;
    v *= 0x81dadef4bc2dd44dull;
    v ^= v >> 33;
    return v;
}

} // namespace effigi
