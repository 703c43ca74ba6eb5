package io.stridekit.tests

import io.stridekit.PaceConfig
import io.stridekit.PaceEstimate
import io.stridekit.PaceMode
import io.stridekit.PaceTracker
import org.junit.jupiter.params.ParameterizedTest
import org.junit.jupiter.params.provider.ValueSource
import org.junit.jupiter.api.Test
import kotlin.test.assertContentEquals
import kotlin.test.assertEquals

/** snapshot() / restore() from Kotlin resume with identical output. */
class SnapshotTest {
    private val run = Sim.run

    @ParameterizedTest(name = "snapshot after {0} % of the run")
    @ValueSource(ints = [0, 10, 50, 90, 100])
    fun `restored tracker continues bit-identically`(percent: Int) {
        val cut = run.samples.size * percent / 100
        val original = PaceTracker.withDefaults()
        val before = original.pushSamples(run.samples.subList(0, cut)).estimates

        val bytes = original.snapshot()
        val restored = PaceTracker.restore(bytes)
        assertEquals(original.config(), restored.config())
        assertEquals(original.estimate(), restored.estimate())
        assertContentEquals(bytes, restored.snapshot())

        val rest = run.samples.subList(cut, run.samples.size)
        val fromOriginal = original.pushSamples(rest).estimates
        val fromRestored = restored.pushSamples(rest).estimates
        assertBitIdentical(fromOriginal, fromRestored, "restored at $percent %")
        assertBitIdentical(run.referenceEstimates, before + fromRestored, "restored vs reference")
        assertContentEquals(original.snapshot(), restored.snapshot())
        original.close()
        restored.close()
    }

    @Test
    fun `configuration survives a snapshot`() {
        val config = PaceConfig(mode = PaceMode.AS_PUBLISHED, initialStepLengthM = 0.95, stationaryAfterS = 3.0)
        PaceTracker(config).use { t ->
            val half = run.samples.subList(0, run.samples.size / 2)
            t.pushSamples(half)
            PaceTracker.restore(t.snapshot()).use { r ->
                assertEquals(config, r.config())
                val rest = run.samples.subList(half.size, run.samples.size)
                val a: List<PaceEstimate> = t.pushSamples(rest).estimates
                val b: List<PaceEstimate> = r.pushSamples(rest).estimates
                assertBitIdentical(a, b, "as-published restored")
            }
        }
    }
}
