package io.stridekit.tests

import io.stridekit.PaceEstimate
import io.stridekit.PaceSample
import io.stridekit.PaceTracker
import io.stridekit.StepSample
import io.stridekit.simulateRun
import org.junit.jupiter.api.Test
import org.junit.jupiter.params.ParameterizedTest
import org.junit.jupiter.params.provider.ValueSource
import kotlin.test.assertEquals
import kotlin.test.assertTrue

/** Pushing a simulated run from Kotlin gives exactly the estimates Rust computed. */
class SimulatedRunTest {
    private val run = Sim.run

    @Test
    fun `the simulated run is not empty`() {
        assertTrue(run.fixes.size > 100, "${run.fixes.size} fixes")
        assertTrue(run.steps.isNotEmpty(), "no step samples")
        assertEquals(run.fixes.size + run.steps.size, run.samples.size)
        assertEquals(0, run.referenceRejected)
        assertEquals(run.fixes.size, run.referenceEstimates.size)
    }

    @Test
    fun `the simulation is deterministic`() {
        assertEquals(run, simulateRun(Sim.SEED, Sim.DURATION_S))
    }

    @Test
    fun `one by one gives the Rust reference`() {
        PaceTracker.withDefaults().use { tracker ->
            val estimates = mutableListOf<PaceEstimate>()
            for (s in run.samples) {
                when (s) {
                    is PaceSample.Fix -> estimates.add(tracker.pushFix(s.fix))
                    is PaceSample.Steps -> tracker.pushSteps(s.sample)
                }
            }
            assertBitIdentical(run.referenceEstimates, estimates, "one by one")
            assertEquals(run.referenceFinal, tracker.estimate())
        }
    }

    @ParameterizedTest(name = "batches of {0}")
    @ValueSource(ints = [1, 2, 7, 10, 100, 1000, 100_000])
    fun `mixed batches give the Rust reference`(size: Int) {
        PaceTracker.withDefaults().use { tracker ->
            val estimates = mutableListOf<PaceEstimate>()
            for (chunk in run.samples.chunked(size)) {
                val r = tracker.pushSamples(chunk)
                assertEquals(emptyList(), r.rejected)
                estimates.addAll(r.estimates)
            }
            assertBitIdentical(run.referenceEstimates, estimates, "batches of $size")
            assertEquals(run.referenceFinal, tracker.estimate())
        }
    }

    @Test
    fun `batches of varying size give the Rust reference`() {
        val sizes = intArrayOf(1, 13, 2, 250, 1, 64, 999, 5)
        PaceTracker.withDefaults().use { tracker ->
            val estimates = mutableListOf<PaceEstimate>()
            var i = 0
            var k = 0
            while (i < run.samples.size) {
                val n = minOf(sizes[k++ % sizes.size], run.samples.size - i)
                val r = tracker.pushSamples(run.samples.subList(i, i + n))
                assertTrue(r.rejected.isEmpty())
                estimates.addAll(r.estimates)
                i += n
            }
            assertBitIdentical(run.referenceEstimates, estimates, "varying batches")
        }
    }

    @Test
    fun `per-stream batches and the packed fast path give the Rust reference`() {
        val records = PaceTracker.withDefaults()
        val packed = PaceTracker.withDefaults()
        val fromRecords = mutableListOf<PaceEstimate>()
        val fromPacked = mutableListOf<PaceEstimate>()
        for (group in streamRuns(run.samples)) {
            if (group.first() is PaceSample.Fix) {
                val fixes = group.map { (it as PaceSample.Fix).fix }
                fromRecords.addAll(records.pushFixes(fixes).estimates)
                fromPacked.addAll(packed.pushFixesPacked(KotlinPacking.fixes(fixes)).estimates)
            } else {
                val steps = group.map { (it as PaceSample.Steps).sample }
                assertTrue(records.pushStepSamples(steps).rejected.isEmpty())
                // The simulated pedometer reports cumulative counts once per second.
                val counts = steps.map { it as StepSample.Count }
                assertTrue(packed.pushStepCountsPacked(KotlinPacking.stepCounts(counts)).rejected.isEmpty())
            }
        }
        assertBitIdentical(run.referenceEstimates, fromRecords, "pushFixes/pushStepSamples")
        assertBitIdentical(run.referenceEstimates, fromPacked, "packed")
        assertTrue(records.snapshot().contentEquals(packed.snapshot()))
        records.close()
        packed.close()
    }
}
