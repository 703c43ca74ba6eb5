package io.stridekit.tests

import io.stridekit.GnssFix
import io.stridekit.PaceConfig
import io.stridekit.PaceException
import io.stridekit.PaceMode
import io.stridekit.PaceTracker
import io.stridekit.SensorStream
import io.stridekit.StepSample
import io.stridekit.defaultPaceConfig
import io.stridekit.packFixes
import io.stridekit.packStepCounts
import io.stridekit.simulateRun
import org.junit.jupiter.api.Test
import kotlin.test.assertContentEquals
import kotlin.test.assertEquals
import kotlin.test.assertFailsWith
import kotlin.test.assertTrue

/** Errors surface as PaceException subclasses and leave the tracker usable. */
class ErrorsTest {
    private fun fix(t: Double) = GnssFix(tS = t, latDeg = 50.2945 + t * 2e-5, lonDeg = 18.6714 + t * 3e-5, horizontalAccuracyM = 4.0)

    @Test
    fun `NaN latitude is NonFinite and the tracker keeps working`() {
        PaceTracker.withDefaults().use { t ->
            t.pushFix(fix(1.0))
            val before = t.snapshot()
            val e = assertFailsWith<PaceException.NonFinite> { t.pushFix(fix(2.0).copy(latDeg = Double.NaN)) }
            assertEquals("lat_deg", e.field)
            assertEquals("lat_deg is not a finite number", e.toString())
            // message is the SDK's sentence (bindings/kotlin-messages.py), not a field dump.
            assertEquals("lat_deg is not a finite number", e.message)
            assertContentEquals(before, t.snapshot(), "a rejected fix changes nothing")
            assertEquals(2.0, t.pushFix(fix(2.0)).tS)
        }
    }

    @Test
    fun `out of range values are OutOfRange`() {
        PaceTracker.withDefaults().use { t ->
            val e = assertFailsWith<PaceException.OutOfRange> { t.pushFix(fix(1.0).copy(latDeg = 91.0)) }
            assertEquals("lat_deg", e.field)
            assertEquals(91.0, e.value)
            assertFailsWith<PaceException.OutOfRange> { t.pushFix(fix(1.0).copy(horizontalAccuracyM = -1.0)) }
            assertFailsWith<PaceException.OutOfRange> { t.pushSteps(StepSample.Cadence(tS = 1.0, stepsPerMin = 1000.0)) }
            t.pushFix(fix(1.0))
        }
    }

    @Test
    fun `time going backwards is TimeNotIncreasing and the tracker keeps working`() {
        PaceTracker.withDefaults().use { t ->
            t.pushFix(fix(10.0))
            val e = assertFailsWith<PaceException.TimeNotIncreasing> { t.pushFix(fix(9.0)) }
            assertEquals(SensorStream.GNSS, e.stream)
            assertEquals(9.0, e.tS)
            assertEquals(10.0, e.lastTS)
            assertFailsWith<PaceException.TimeNotIncreasing> { t.pushFix(fix(10.0)) }

            t.pushSteps(StepSample.Count(tS = 10.0, steps = 100L))
            val s = assertFailsWith<PaceException.TimeNotIncreasing> { t.pushSteps(StepSample.Event(tS = 9.5)) }
            assertEquals(SensorStream.STEPS, s.stream)

            // Still accepts later samples of both streams.
            t.pushSteps(StepSample.Count(tS = 11.0, steps = 103L))
            assertEquals(11.0, t.pushFix(fix(11.0)).tS)
        }
    }

    @Test
    fun `bad snapshot bytes are InvalidSnapshot`() {
        val good = PaceTracker.withDefaults().use { it.pushFix(fix(1.0)); it.snapshot() }
        val corrupted = good.copyOf().also { it[it.size / 2] = (it[it.size / 2].toInt() xor 1).toByte() }
        for (bytes in listOf(ByteArray(0), "garbage!garbage!".toByteArray(), good.copyOf(good.size - 3), corrupted)) {
            val e = assertFailsWith<PaceException.InvalidSnapshot> { PaceTracker.restore(bytes) }
            assertTrue(e.toString().startsWith("cannot restore snapshot"), e.toString())
        }
        PaceTracker.restore(good).use { assertEquals(1.0, it.estimate()!!.tS) }
    }

    @Test
    fun `invalid configurations are InvalidConfig`() {
        assertFailsWith<PaceException.InvalidConfig> { PaceTracker(PaceConfig(mode = PaceMode.ADAPTIVE, initialStepLengthM = 9.0)) }
        val e = assertFailsWith<PaceException.InvalidConfig> {
            PaceTracker(PaceConfig(mode = PaceMode.AS_PUBLISHED, stationaryAfterS = -1.0))
        }
        assertTrue(e.reason.contains("stationary_after_s"), e.reason)
    }

    @Test
    fun `record defaults are the core defaults`() {
        assertEquals(defaultPaceConfig(), PaceConfig(mode = PaceMode.ADAPTIVE))
        PaceTracker(PaceConfig(mode = PaceMode.AS_PUBLISHED, initialStepLengthM = 1.05)).use {
            assertEquals(PaceConfig(PaceMode.AS_PUBLISHED, 1.05, 2.0), it.config())
        }
    }

    @Test
    fun `batches report rejected samples by index and push the rest`() {
        PaceTracker.withDefaults().use { t ->
            val batch = listOf(fix(1.0), fix(2.0).copy(lonDeg = Double.POSITIVE_INFINITY), fix(3.0), fix(2.5), fix(4.0))
            val r = t.pushFixes(batch)
            assertEquals(listOf(1, 3), r.rejected.map { it.index })
            assertTrue(r.rejected[0].error is PaceException.NonFinite)
            assertTrue(r.rejected[1].error is PaceException.TimeNotIncreasing)
            assertEquals(r.rejected[1].error.toString(), r.rejected[1].reason)
            assertEquals(listOf(1.0, 3.0, 4.0), r.estimates.map { it.tS })
            assertEquals(t.estimate(), r.latest)
        }
    }

    @Test
    fun `packed buffers of a wrong length are InvalidBuffer`() {
        PaceTracker.withDefaults().use { t ->
            assertFailsWith<PaceException.InvalidBuffer> { t.pushFixesPacked(ByteArray(57)) }
            assertFailsWith<PaceException.InvalidBuffer> { t.pushStepCountsPacked(ByteArray(15)) }
            assertEquals(1, t.pushFixesPacked(KotlinPacking.fixes(listOf(fix(1.0)))).estimates.size)
        }
    }

    @Test
    fun `Kotlin packing matches the documented layout`() {
        val fixes = listOf(fix(1.0), fix(2.0).copy(altM = 120.0, speedMps = 3.2, speedAccuracyMps = 0.3), fix(3.0).copy(horizontalAccuracyM = null))
        assertContentEquals(packFixes(fixes), KotlinPacking.fixes(fixes))
        val counts = listOf(StepSample.Count(0.5, 0L), StepSample.Count(1.5, Long.MAX_VALUE))
        assertContentEquals(packStepCounts(counts), KotlinPacking.stepCounts(counts))
    }

    @Test
    fun `simulateRun validates its duration`() {
        assertFailsWith<PaceException.NonFinite> { simulateRun(1uL, Double.NaN) }
        assertFailsWith<PaceException.OutOfRange> { simulateRun(1uL, -5.0) }
    }
}
