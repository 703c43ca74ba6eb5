package io.stridekit.tests

import io.stridekit.GnssFix
import io.stridekit.PaceSample
import io.stridekit.PaceTracker
import io.stridekit.simulateRun
import org.junit.jupiter.api.Tag
import org.junit.jupiter.api.Test

/**
 * Cost of pushing through the FFI, in ns per sample, for batches of 1, 10, 100, 1000.
 * Not part of the default test run: `mvn -B -f tests/pom.xml test -Pbench`
 * (add `-Dstridekit.libdir=$PWD/target/release` after `cargo build --release -p stridekit`
 * for numbers that mean something: the default library is a debug build).
 */
@Tag("bench")
class BatchPushBenchTest {
    private val run = simulateRun(1uL, 2400.0)
    private val minMeasureNanos = (System.getProperty("stridekit.bench.seconds") ?: "1.5").toDouble() * 1e9

    /** ns per sample of pushing all [n] samples in chunks through [push], fresh tracker per pass. */
    private fun measure(n: Int, push: (PaceTracker) -> Unit): Double {
        fun pass(): Long {
            val tracker = PaceTracker.withDefaults()
            val t0 = System.nanoTime()
            push(tracker)
            val dt = System.nanoTime() - t0
            tracker.close()
            return dt
        }
        // Warm up the JIT and the allocator.
        var warm = 0L
        while (warm < minMeasureNanos / 3) warm += pass()
        var total = 0L
        var samples = 0L
        while (total < minMeasureNanos || samples < 3L * n) {
            total += pass()
            samples += n
        }
        return total.toDouble() / samples
    }

    @Test
    fun `batch push cost per sample`() {
        val samples: List<PaceSample> = run.samples
        val fixes: List<GnssFix> = run.fixes
        val lib = System.getProperty("jna.library.path")
        println()
        println("stridekit batch push benchmark (library in $lib)")
        println("${samples.size} mixed samples / ${fixes.size} fixes per pass, fresh tracker per pass")
        println()
        println("| batch | pushSamples(List<PaceSample>) | pushFixes(List<GnssFix>) | pushFixesPacked(ByteArray) |")
        println("|------:|------------------------------:|-------------------------:|---------------------------:|")
        for (batch in listOf(1, 10, 100, 1000)) {
            val sampleChunks = samples.chunked(batch)
            val fixChunks = fixes.chunked(batch)
            val mixed = measure(samples.size) { t -> for (c in sampleChunks) t.pushSamples(c) }
            val records = measure(fixes.size) { t -> for (c in fixChunks) t.pushFixes(c) }
            // Packing in Kotlin is part of the cost an app pays, so it is timed.
            val packed = measure(fixes.size) { t -> for (c in fixChunks) t.pushFixesPacked(KotlinPacking.fixes(c)) }
            println(String.format("| %5d | %26.0f ns | %21.0f ns | %23.0f ns |", batch, mixed, records, packed))
        }
        println()
    }
}
