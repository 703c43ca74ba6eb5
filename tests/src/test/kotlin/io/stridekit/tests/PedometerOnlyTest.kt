package io.stridekit.tests

import io.stridekit.AccelSample
import io.stridekit.AccelStepModel
import io.stridekit.PaceCalibration
import io.stridekit.PaceException
import io.stridekit.PaceConfig
import io.stridekit.PaceMode
import io.stridekit.PaceSource
import io.stridekit.PaceTracker
import io.stridekit.StepSample
import io.stridekit.paceCalibrationFromText
import io.stridekit.paceCalibrationToText
import org.junit.jupiter.api.Test
import kotlin.test.assertEquals
import kotlin.test.assertFailsWith
import kotlin.test.assertNotNull
import kotlin.test.assertNull
import kotlin.test.assertTrue

/** Pace with no GNSS at all (treadmill, indoor track, watch without GNSS). */
class PedometerOnlyTest {
    private val cadence = 170.0 / 60.0

    private fun counts(tracker: PaceTracker, seconds: Int) {
        for (i in 1..seconds) {
            tracker.pushSteps(StepSample.Count(tS = i.toDouble(), steps = (cadence * i).toLong()))
        }
    }

    @Test
    fun `step counts alone give pedometer speed with an initial step length`() {
        PaceTracker(PaceConfig(mode = PaceMode.ADAPTIVE, initialStepLengthM = 1.1)).use { t ->
            counts(t, 30)
            val e = assertNotNull(t.estimate())
            assertEquals(PaceSource.PEDOMETER, e.source)
            assertEquals(0.0, e.gnssWeight)
            val want = cadence * 1.1
            assertTrue(Math.abs(e.speedMps - want) < 0.05 * want, "speed ${e.speedMps}, want $want")
            assertNotNull(e.paceSPerKm)
            assertTrue(e.distanceM > 0.85 * want * 28, "distance ${e.distanceM}")
            assertNull(t.calibration(), "nothing learned without GNSS")
        }
    }

    @Test
    fun `a stored calibration gives calibrated speed and survives a snapshot`() {
        val cal = PaceCalibration(stepLengthM = 0.95, cadenceSpm = 170.0, slopeMPerSpm = 0.008, stepLengthStdM = 0.02)
        PaceTracker(PaceConfig(mode = PaceMode.ADAPTIVE, calibration = cal)).use { t ->
            for (i in 1..20) {
                t.pushSteps(StepSample.Cadence(tS = i.toDouble(), stepsPerMin = 170.0))
            }
            val e = assertNotNull(t.estimate())
            assertEquals(PaceSource.PEDOMETER, e.source)
            assertTrue(Math.abs(e.speedMps - cadence * 0.95) < 0.03, "speed ${e.speedMps}")
            val restored = PaceTracker.restore(t.snapshot())
            assertEquals(cal, restored.config().calibration)
            assertEquals(t.estimate(), restored.estimate())
            assertNotNull(t.calibration())
            restored.close()
        }
    }

    @Test
    fun `a carried accelerometer model paces raw acceleration without GNSS`() {
        val model = AccelStepModel(
            aMS = 0.38, bMPerM2ps4 = 0.0, cM = 0.1,
            refFrequencyHz = 1.66, refVarianceM2ps4 = 6.6,
            aStdMS = 0.14, bStdMPerM2ps4 = 0.002, lengthStdM = 0.016,
        )
        val cal = PaceCalibration(
            stepLengthM = 0.42, cadenceSpm = 98.0, slopeMPerSpm = 0.0083, stepLengthStdM = 0.4,
            accelModel = model,
        )
        PaceTracker(PaceConfig(mode = PaceMode.ADAPTIVE, calibration = cal)).use { t ->
            // 30 s of a walk at 1.8 steps/s (100 Hz; a bounce of ±3 m/s² per step).
            val f = 1.8
            val samples = (0 until 3000).map { i ->
                val ts = i / 100.0
                AccelSample(tS = ts, xMps2 = 0.3, yMps2 = 0.2, zMps2 = 9.81 + 3.0 * Math.sin(2 * Math.PI * f * ts))
            }
            assertTrue(t.pushAccelSamples(samples).rejected.isEmpty())
            val e = assertNotNull(t.estimate())
            assertEquals(PaceSource.PEDOMETER, e.source)
            // L = A·F + B·SV + C at these steps' features (B ≈ 0): ≈ 0.78 m.
            val l = assertNotNull(e.stepLengthM)
            assertTrue(Math.abs(l - (0.38 * f + 0.1)) < 0.05, "step length $l")
            assertEquals(model, t.calibration()?.accelModel, "carried on unchanged without GNSS")
            val restored = PaceTracker.restore(t.snapshot())
            assertEquals(cal, restored.config().calibration)
            assertEquals(t.estimate(), restored.estimate())
            restored.close()
        }
        val bad = cal.copy(accelModel = model.copy(lengthStdM = 0.0))
        assertFailsWith<PaceException.InvalidConfig> { PaceTracker(PaceConfig(mode = PaceMode.ADAPTIVE, calibration = bad)) }

        // Stored as text with the user's profile, read back exactly.
        val text = paceCalibrationToText(cal)
        assertTrue(text.startsWith("stridekit-pace-calibration 1\n"), text)
        assertEquals(cal, paceCalibrationFromText(text))
        val lineOnly = cal.copy(accelModel = null)
        assertEquals(lineOnly, paceCalibrationFromText(paceCalibrationToText(lineOnly)))
        assertFailsWith<PaceException.InvalidConfig> { paceCalibrationToText(bad) }
        assertFailsWith<PaceException.InvalidConfig> { paceCalibrationFromText("stridekit-pace-calibration 2\n") }
        assertFailsWith<PaceException.InvalidConfig> { paceCalibrationFromText(text.replace("line 0.42", "line NaN")) }
    }
}
