package io.stridekit.tests

import io.stridekit.PhoneNavigator
import io.stridekit.PhonePlacement
import io.stridekit.pdrReferenceReplay
import io.stridekit.simulatePhoneWalk
import org.junit.jupiter.api.Tag
import org.junit.jupiter.api.Test

/**
 * Cost per IMU sample of `PhoneNavigator.pushImuPacked` from Kotlin (packing excluded:
 * the buffers are cut beforehand; the FFI copy, decoding, the lock and the whole PDR
 * pipeline with magnetometer included) at batches of 1, 10, 100 and 1 000 samples,
 * beside the same pipeline driven from Rust (`pdrReferenceReplay`: one FFI call for
 * the whole walk, so its cost per sample is the Rust cost). Input: a simulated 100 Hz
 * walk with the phone in hand. Not part of the default test run:
 * `mvn -B -f tests/pom.xml test -Pbench -Dtest=NavigatorBenchTest -Dstridekit.libdir=$PWD/target/release`
 * after `cargo build --release -p stridekit`.
 */
@Tag("bench")
class NavigatorBenchTest {
    private val walk = simulatePhoneWalk(seed = 5uL, placement = PhonePlacement.IN_HAND, speedMps = 1.3, durationS = 300.0)
    private val minMeasureNanos = (System.getProperty("stridekit.bench.seconds") ?: "2").toDouble() * 1e9

    private fun measure(samples: Int, pass: () -> Unit): Double {
        var warm = 0L
        while (warm < minMeasureNanos / 3) {
            val t0 = System.nanoTime(); pass(); warm += System.nanoTime() - t0
        }
        var total = 0L
        var n = 0L
        while (total < minMeasureNanos || n < 3L * samples) {
            val t0 = System.nanoTime(); pass(); total += System.nanoTime() - t0
            n += samples
        }
        return total.toDouble() / n
    }

    @Test
    fun `navigator push cost per sample`() {
        val packed = walk.imuPacked
        val n = packed.size / 80
        println()
        println("PhoneNavigator, ${n} samples per pass (simulated 100 Hz walk in hand, magnetometer), library in ${System.getProperty("jna.library.path")}")
        val rust = measure(n) { pdrReferenceReplay(packed, null) }
        println()
        println("| batch | pushImuPacked from Kotlin, ns per sample | Rust (one call per pass), ns per sample |")
        println("|------:|------:|------:|")
        for (batch in listOf(1, 10, 100, 1000)) {
            val chunks = (0 until n step batch).map { packed.copyOfRange(it * 80, minOf(n, it + batch) * 80) }
            val kotlin = measure(n) {
                PhoneNavigator.withDefaults().use { nav -> for (c in chunks) nav.pushImuPacked(c) }
            }
            println(String.format("| %5d | %8.0f | %8.0f |", batch, kotlin, rust))
        }
        println()
    }
}
