package io.stridekit.tests

import io.stridekit.GnssFix
import io.stridekit.PaceEstimate
import io.stridekit.PaceSample
import io.stridekit.SimulatedRun
import io.stridekit.StepSample
import io.stridekit.simulateRun
import java.nio.ByteBuffer
import java.nio.ByteOrder
import kotlin.test.assertEquals
import kotlin.test.fail

/** One simulated run (computed once per JVM) with Rust's reference estimates. */
object Sim {
    const val SEED: ULong = 20_260_101uL
    const val DURATION_S: Double = 900.0

    val run: SimulatedRun by lazy { simulateRun(SEED, DURATION_S) }
}

/** The raw bits of every field, so that equality means bit-identical (NaN- and ±0-exact). */
fun PaceEstimate.bits(): List<Any?> = listOf(
    tS.toRawBits(),
    speedMps.toRawBits(),
    paceSPerKm?.toRawBits(),
    speedStdMps?.toRawBits(),
    cadenceSpm?.toRawBits(),
    stepLengthM?.toRawBits(),
    gnssWeight.toRawBits(),
    distanceM.toRawBits(),
    source,
)

fun assertBitIdentical(expected: List<PaceEstimate>, actual: List<PaceEstimate>, what: String) {
    assertEquals(expected.size, actual.size, "$what: number of estimates")
    for (i in expected.indices) {
        if (expected[i].bits() != actual[i].bits()) {
            fail("$what: estimate $i differs\n  expected ${expected[i]}\n  actual   ${actual[i]}")
        }
    }
}

/** Packs fixes as the documented 56-byte little-endian records (NaN for null). */
object KotlinPacking {
    const val FIX_BYTES = 56
    const val STEP_COUNT_BYTES = 16

    fun fixes(fixes: List<GnssFix>): ByteArray {
        val b = ByteBuffer.allocate(fixes.size * FIX_BYTES).order(ByteOrder.LITTLE_ENDIAN)
        for (f in fixes) {
            b.putDouble(f.tS).putDouble(f.latDeg).putDouble(f.lonDeg)
            b.putDouble(f.altM ?: Double.NaN)
            b.putDouble(f.horizontalAccuracyM ?: Double.NaN)
            b.putDouble(f.speedMps ?: Double.NaN)
            b.putDouble(f.speedAccuracyMps ?: Double.NaN)
        }
        return b.array()
    }

    fun stepCounts(counts: List<StepSample.Count>): ByteArray {
        val b = ByteBuffer.allocate(counts.size * STEP_COUNT_BYTES).order(ByteOrder.LITTLE_ENDIAN)
        for (c in counts) b.putDouble(c.tS).putLong(c.steps.toLong())
        return b.array()
    }
}

/** Splits samples into runs of consecutive fixes / consecutive step samples. */
fun streamRuns(samples: List<PaceSample>): List<List<PaceSample>> {
    val out = mutableListOf<MutableList<PaceSample>>()
    for (s in samples) {
        val last = out.lastOrNull()
        if (last != null && last.first()::class == s::class) last.add(s) else out.add(mutableListOf(s))
    }
    return out
}
